#include "texture_snr.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace room_reverb::core::stereo_detail {
namespace {

// Below this the noise is taken as the grey levels' own quantisation (a uniform step of one
// level: sigma = 1 / sqrt(12)), so that a clean rendered image does not divide by zero.
constexpr double kQuantisationSigma = 0.2887;

}  // namespace

double pixelNoiseSigma(const cv::Mat& grey) {
  if (grey.rows < 3 || grey.cols < 3) return kQuantisationSigma;
  const cv::Mat mask = (cv::Mat_<float>(3, 3) << 1, -2, 1, -2, 4, -2, 1, -2, 1);
  cv::Mat response;
  cv::filter2D(grey, response, CV_32F, mask, cv::Point(-1, -1), 0.0, cv::BORDER_REFLECT);
  // The median of |response|, grouped by whole grey levels and interpolated within its
  // level: on 8-bit images the response is a whole number, and the plain median would move
  // sigma in steps of a quarter of a grey level (1.4826 / 6). Every second pixel of every
  // second row: a quarter of the work.
  constexpr int kLevels = 1024;
  std::vector<long> counts(kLevels + 1, 0);
  long n = 0;
  for (int r = 1; r + 1 < response.rows; r += 2) {
    const float* p = response.ptr<float>(r);
    for (int c = 1; c + 1 < response.cols; c += 2) {
      ++counts[static_cast<std::size_t>(std::min<long>(kLevels, std::lround(std::abs(p[c]))))];
      ++n;
    }
  }
  if (n == 0) return kQuantisationSigma;
  long below = 0;
  int level = 0;
  while (level < kLevels && 2 * (below + counts[static_cast<std::size_t>(level)]) < n) below += counts[static_cast<std::size_t>(level++)];
  // Level k holds |response| in [k - 0.5, k + 0.5), level 0 in [0, 0.5).
  const double lower = level == 0 ? 0.0 : level - 0.5, width = level == 0 ? 0.5 : 1.0;
  const double in_level = static_cast<double>(std::max(1L, counts[static_cast<std::size_t>(level)]));
  const double median = lower + width * (0.5 * static_cast<double>(n) - static_cast<double>(below)) / in_level;
  return std::max(kQuantisationSigma, 1.4826 * median / 6.0);
}

cv::Mat epipolarTextureSnr(const EpipolarImage& image, double noise_sigma, int half_window) {
  const double sigma = std::max(noise_sigma, kQuantisationSigma);
  cv::Mat energy;
  cv::boxFilter(image.dx.mul(image.dx), energy, CV_32F, cv::Size(2 * half_window + 1, 2 * half_window + 1),
                cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  cv::Mat snr;
  energy.convertTo(snr, CV_32F, 1.0 / (0.5 * sigma * sigma), -1.0);
  return snr;
}

}  // namespace room_reverb::core::stereo_detail
