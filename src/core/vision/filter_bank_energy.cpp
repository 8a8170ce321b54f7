#include "filter_bank_energy.h"

#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace room_reverb::core::material_detail {
namespace {

// Sampled Gaussian (order 0) and its first and second derivatives, radius 3 sigma.
cv::Mat gaussianKernel(double sigma, int order) {
  const int radius = static_cast<int>(std::ceil(3.0 * sigma));
  cv::Mat k(2 * radius + 1, 1, CV_32F);
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) sum += std::exp(-0.5 * i * i / (sigma * sigma));
  for (int i = -radius; i <= radius; ++i) {
    const double g = std::exp(-0.5 * i * i / (sigma * sigma)) / sum;
    const double s2 = sigma * sigma;
    const double value = order == 0 ? g : order == 1 ? -i / s2 * g : (i * i / (s2 * s2) - 1.0 / s2) * g;
    k.at<float>(i + radius) = static_cast<float>(value);
  }
  if (order == 2) k -= cv::mean(k)[0];  // exactly zero response to a constant
  return k;
}

cv::Mat filtered(const cv::Mat& image, double sigma, int order_x, int order_y) {
  cv::Mat out;
  cv::sepFilter2D(image, out, CV_32F, gaussianKernel(sigma, order_x), gaussianKernel(sigma, order_y), cv::Point(-1, -1),
                  0.0, cv::BORDER_REFLECT);
  return out;
}

}  // namespace

void filterBankEnergies(const cv::Mat& log_grey, const cv::Mat& mask, float* energies) {
  CV_Assert(log_grey.type() == CV_32FC1 && mask.type() == CV_8UC1 && log_grey.size() == mask.size());
  constexpr std::array<double, kFilterScales> kSigmas = {1.0, 2.0, 4.0};
  constexpr double kPi = 3.14159265358979323846;
  for (int s = 0; s < kFilterScales; ++s) {
    const double sigma = kSigmas[static_cast<std::size_t>(s)];
    // Scale normalisation (sigma^order) makes a pattern's energy independent of the scale
    // it is met at, so the scales compare the texture's spectrum, not the filters' gains.
    const cv::Mat lx = filtered(log_grey, sigma, 1, 0) * sigma, ly = filtered(log_grey, sigma, 0, 1) * sigma;
    const double s2 = sigma * sigma;
    const cv::Mat lxx = filtered(log_grey, sigma, 2, 0) * s2, lyy = filtered(log_grey, sigma, 0, 2) * s2;
    const cv::Mat lxy = filtered(log_grey, sigma, 1, 1) * s2;
    std::array<double, kFilterEnergiesPerScale> sum{};
    double count = 0.0;
    for (int y = 0; y < mask.rows; ++y) {
      const unsigned char* m = mask.ptr<unsigned char>(y);
      for (int x = 0; x < mask.cols; ++x) {
        if (!m[x]) continue;
        const double gx = lx.at<float>(y, x), gy = ly.at<float>(y, x);
        const double gxx = lxx.at<float>(y, x), gyy = lyy.at<float>(y, x), gxy = lxy.at<float>(y, x);
        for (int o = 0; o < 4; ++o) {
          const double c = std::cos(o * kPi / 4.0), n = std::sin(o * kPi / 4.0);
          const double first = c * gx + n * gy;
          const double second = c * c * gxx + 2.0 * c * n * gxy + n * n * gyy;
          sum[static_cast<std::size_t>(o)] += first * first;
          sum[static_cast<std::size_t>(4 + o)] += second * second;
        }
        count += 1.0;
      }
    }
    for (int k = 0; k < kFilterEnergiesPerScale; ++k) {
      // The floor keeps a flat, noiseless region finite; it is far below any real texture.
      const double mean = count > 0.0 ? sum[static_cast<std::size_t>(k)] / count : 0.0;
      energies[s * kFilterEnergiesPerScale + k] = static_cast<float>(std::log(mean + 1e-8));
    }
  }
}

}  // namespace room_reverb::core::material_detail
