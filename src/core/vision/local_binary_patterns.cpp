#include "local_binary_patterns.h"

#include <array>
#include <cmath>

namespace room_reverb::core::material_detail {
namespace {

// 2 % brighter: above the generator's sensor noise on the pale surfaces (about 1 % at
// sigma 2 on grey 200), well below the contrast of joints, grain and weave.
constexpr float kRelativeMargin = 0.02f;

float bilinear(const cv::Mat& image, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const float* r0 = image.ptr<float>(y0);
  const float* r1 = image.ptr<float>(std::min(y0 + 1, image.rows - 1));
  const int x1 = std::min(x0 + 1, image.cols - 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x1]);
}

}  // namespace

void lbpHistogram(const cv::Mat& grey, const cv::Mat& mask, double radius_px, float* bins) {
  CV_Assert(grey.type() == CV_32FC1 && mask.type() == CV_8UC1 && grey.size() == mask.size());
  std::array<double, 8> dx{}, dy{};
  for (int p = 0; p < 8; ++p) {
    const double angle = 2.0 * 3.14159265358979323846 * p / 8.0;
    // Round away the tiny residues of cos and sin so axis neighbours fall on pixels.
    dx[p] = std::round(radius_px * std::cos(angle) * 1e6) / 1e6;
    dy[p] = -std::round(radius_px * std::sin(angle) * 1e6) / 1e6;
  }
  std::array<double, kLbpBins> count{};
  double total = 0.0;
  const int margin = static_cast<int>(std::ceil(radius_px));
  for (int y = margin; y < grey.rows - margin; ++y) {
    const unsigned char* m = mask.ptr<unsigned char>(y);
    const float* g = grey.ptr<float>(y);
    for (int x = margin; x < grey.cols - margin; ++x) {
      if (!m[x]) continue;
      const float threshold = g[x] * (1.0f + kRelativeMargin);
      std::array<bool, 8> bit{};
      int ones = 0;
      for (int p = 0; p < 8; ++p) {
        bit[p] = bilinear(grey, x + dx[p], y + dy[p]) > threshold;
        ones += bit[p] ? 1 : 0;
      }
      int transitions = 0;
      for (int p = 0; p < 8; ++p) transitions += bit[p] != bit[(p + 1) % 8] ? 1 : 0;
      count[transitions <= 2 ? ones : 9] += 1.0;
      total += 1.0;
    }
  }
  for (int b = 0; b < kLbpBins; ++b) bins[b] = total > 0.0 ? static_cast<float>(count[b] / total) : 0.0f;
}

}  // namespace room_reverb::core::material_detail
