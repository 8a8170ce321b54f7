#include "photometric_match.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace room_reverb::core {
namespace {

struct Line {
  double gain = 1.0, offset = 0.0;
  bool ok = false;
};

// y = gain x + offset over the pairs in `use`, from at least `min_pairs` of them.
Line leastSquares(const std::vector<float>& x, const std::vector<float>& y, const std::vector<char>& use, double min_pairs) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, n = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!use[i]) continue;
    sx += x[i], sy += y[i], sxx += double(x[i]) * x[i], sxy += double(x[i]) * y[i], n += 1.0;
  }
  Line line;
  const double var = sxx - sx * sx / std::max(n, 1.0);
  if (n < min_pairs || var <= 1e-6 * n) return line;
  line.gain = (sxy - sx * sy / n) / var;
  line.offset = (sy - line.gain * sx) / n;
  line.ok = true;
  return line;
}

// Cumulative histogram of one channel over the rows [first, last), without 0 and 255.
std::array<double, 256> cumulative(const cv::Mat& image, int channel, int first, int last) {
  std::array<double, 256> histogram{};
  const int channels = image.channels();
  for (int r = first; r < last; ++r) {
    const std::uint8_t* row = image.ptr<std::uint8_t>(r);
    for (int c = 0; c < image.cols; ++c) histogram[row[c * channels + channel]] += 1.0;
  }
  histogram[0] = histogram[255] = 0.0;
  for (int v = 1; v < 256; ++v) histogram[v] += histogram[v - 1];
  return histogram;
}

// The grey level below which a share q of the counted pixels lie (linear within a level).
float quantile(const std::array<double, 256>& cdf, double q) {
  const double target = q * cdf[255];
  for (int v = 1; v < 256; ++v) {
    if (cdf[v] >= target) {
      const double below = cdf[v - 1], step = cdf[v] - below;
      return static_cast<float>(step > 0.0 ? v - 0.5 + (target - below) / step : v);
    }
  }
  return 255.0f;
}

// A map that inverts or crushes the image is no exposure difference.
bool plausible(const Line& line) { return line.ok && line.gain > 0.25 && line.gain < 4.0; }

}  // namespace

PhotometricMap photometricMapFromQuantiles(const cv::Mat& top, const cv::Mat& bottom, double polar_cap_deg) {
  CV_Assert(top.size() == bottom.size() && top.type() == bottom.type() && top.depth() == CV_8U);
  PhotometricMap map;
  const int cap = static_cast<int>(std::ceil(polar_cap_deg / 180.0 * top.rows));
  const int first = std::min(cap, top.rows / 2), last = std::max(top.rows - cap, first + 1);
  for (int ch = 0; ch < top.channels() && ch < 3; ++ch) {
    const auto a = cumulative(top, ch, first, last), b = cumulative(bottom, ch, first, last);
    if (a[255] < 200.0 || b[255] < 200.0) continue;
    std::vector<float> x, y;
    for (int k = 2; k <= 98; ++k) x.push_back(quantile(b, k / 100.0)), y.push_back(quantile(a, k / 100.0));
    const Line line = leastSquares(x, y, std::vector<char>(x.size(), 1), 10.0);
    if (!plausible(line)) continue;
    map.gain[ch] = line.gain;
    map.offset[ch] = line.offset;
  }
  return map;
}

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
    Line line = leastSquares(x, y, use, 200.0);
    if (!line.ok) continue;
    // Refit without the fifth of pairs that fit worst.
    std::vector<float> residual(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) residual[i] = std::abs(y[i] - static_cast<float>(line.gain * x[i] + line.offset));
    std::vector<float> sorted = residual;
    const std::size_t keep = sorted.size() * 4 / 5;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(keep), sorted.end());
    const float limit = sorted[keep];
    for (std::size_t i = 0; i < x.size(); ++i) use[i] = residual[i] <= limit;
    line = leastSquares(x, y, use, 200.0);
    if (!plausible(line)) continue;
    map.gain[ch] = line.gain;
    map.offset[ch] = line.offset;
  }
  return map;
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
