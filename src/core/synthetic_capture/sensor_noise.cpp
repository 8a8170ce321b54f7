#include "sensor_noise.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "value_noise.h"

namespace room_reverb::core::capture_detail {

cv::Mat exposed(const cv::Mat& color, double gain, const Eigen::Vector3d& white_balance_rgb) {
  CV_Assert(color.type() == CV_32FC3);
  cv::Mat out;
  cv::multiply(color, cv::Scalar(gain * white_balance_rgb[2], gain * white_balance_rgb[1], gain * white_balance_rgb[0]), out);
  return out;
}

cv::Mat quantizeWithNoise(const cv::Mat& color, double sigma, std::uint64_t seed, std::uint64_t stream) {
  CV_Assert(color.type() == CV_32FC3);
  cv::Mat out(color.size(), CV_8UC3);
  const std::uint64_t salt = hashCombine(hashCombine(seed, 0x5e9502ULL), stream);
  for (int row = 0; row < color.rows; ++row) {
    const float* in = color.ptr<float>(row);
    unsigned char* o = out.ptr<unsigned char>(row);
    for (int i = 0; i < 3 * color.cols; ++i) {
      double value = in[i];
      if (sigma > 0.0) {
        // Box-Muller from two hashed uniforms (u1 kept away from 0 for the logarithm).
        const double u1 = 1.0 - latticeUnit(salt, row, 2 * i);
        const double u2 = latticeUnit(salt, row, 2 * i + 1);
        value += sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
      }
      o[i] = static_cast<unsigned char>(std::clamp(std::lround(value), 0L, 255L));
    }
  }
  return out;
}

cv::Mat jpegRoundTrip(const cv::Mat& image, int quality) {
  CV_Assert(image.type() == CV_8UC3 && quality >= 1 && quality <= 100);
  std::vector<unsigned char> bytes;
  cv::imencode(".jpg", image, bytes, {cv::IMWRITE_JPEG_QUALITY, quality});
  return cv::imdecode(bytes, cv::IMREAD_COLOR);
}

}  // namespace room_reverb::core::capture_detail
