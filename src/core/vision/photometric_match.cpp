#include "photometric_match.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace room_reverb::core {
namespace {

struct Line {
  double gain = 1.0, offset = 0.0;
  bool ok = false;
};

// Fewer pairs than this say nothing about a channel.
constexpr double kMinPairs = 200.0;

// y = gain x + offset over the pairs in `use`.
Line leastSquares(const std::vector<float>& x, const std::vector<float>& y, const std::vector<char>& use) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, n = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!use[i]) continue;
    sx += x[i], sy += y[i], sxx += double(x[i]) * x[i], sxy += double(x[i]) * y[i], n += 1.0;
  }
  Line line;
  const double var = sxx - sx * sx / std::max(n, 1.0);
  if (n < kMinPairs || var <= 1e-6 * n) return line;
  line.gain = (sxy - sx * sy / n) / var;
  line.offset = (sy - line.gain * sx) / n;
  line.ok = true;
  return line;
}

// A map that inverts or crushes the image is no exposure difference.
bool plausible(const Line& line) { return line.ok && line.gain > 0.25 && line.gain < 4.0; }

}  // namespace

PhotometricMap photometricMapFromMatches(const cv::Mat& top, const cv::Mat& bottom, const cv::Mat& disparity_px, int step) {
  CV_Assert(top.size() == bottom.size() && top.type() == bottom.type() && top.depth() == CV_8U &&
            disparity_px.type() == CV_32FC1 && disparity_px.size() == top.size() && step >= 1);
  const int channels = top.channels();
  PhotometricMap map;
  for (int ch = 0; ch < channels && ch < 3; ++ch) {
    std::vector<float> x, y;
    for (int r = 0; r < top.rows; r += step) {
      const float* d = disparity_px.ptr<float>(r);
      const std::uint8_t* t = top.ptr<std::uint8_t>(r);
      for (int c = 0; c < top.cols; c += step) {
        if (!std::isfinite(d[c])) continue;
        // The bottom image between its rows, so that the pairs are not blurred by rounding.
        const double at = r - d[c];
        const int r0 = static_cast<int>(std::floor(at));
        if (r0 < 0 || r0 + 1 >= top.rows) continue;
        const double w = at - r0;
        const int a = t[c * channels + ch];
        const int b0 = bottom.ptr<std::uint8_t>(r0)[c * channels + ch], b1 = bottom.ptr<std::uint8_t>(r0 + 1)[c * channels + ch];
        if (a == 0 || a == 255 || b0 == 0 || b0 == 255 || b1 == 0 || b1 == 255) continue;
        x.push_back(static_cast<float>((1.0 - w) * b0 + w * b1));
        y.push_back(static_cast<float>(a));
      }
    }
    std::vector<char> use(x.size(), 1);
    Line line = leastSquares(x, y, use);
    if (!line.ok) continue;
    // Refit without the fifth of pairs that fit worst.
    std::vector<float> residual(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) residual[i] = std::abs(y[i] - static_cast<float>(line.gain * x[i] + line.offset));
    std::vector<float> sorted = residual;
    const std::size_t keep = sorted.size() * 4 / 5;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(keep), sorted.end());
    const float limit = sorted[keep];
    for (std::size_t i = 0; i < x.size(); ++i) use[i] = residual[i] <= limit;
    line = leastSquares(x, y, use);
    if (!plausible(line)) continue;
    map.gain[ch] = line.gain;
    map.offset[ch] = line.offset;
  }
  return map;
}

double largestLevelChange(const PhotometricMap& map) {
  double largest = 0.0;
  for (int ch = 0; ch < 3; ++ch) {
    for (const double level : {32.0, 224.0}) largest = std::max(largest, std::abs(map.gain[ch] * level + map.offset[ch] - level));
  }
  return largest;
}

cv::Mat applyPhotometricMap(const cv::Mat& bottom, const PhotometricMap& map) {
  const int channels = bottom.channels();
  std::vector<cv::Mat> planes;
  cv::split(bottom, planes);
  for (int ch = 0; ch < channels && ch < 3; ++ch) planes[ch].convertTo(planes[ch], CV_8U, map.gain[ch], map.offset[ch]);
  cv::Mat out;
  cv::merge(planes, out);
  return out;
}

}  // namespace room_reverb::core
