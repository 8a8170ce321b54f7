#include "local_binary_patterns.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace room_reverb::core::material_detail {
namespace {

// 2 % brighter: above the generator's sensor noise on the pale surfaces (about 1 % at
// sigma 2 on grey 200), well below the contrast of joints, grain and weave.
constexpr float kRelativeMargin = 0.02f;

// Where the neighbour at offset `d` of each pixel coordinate in [margin, size - margin)
// falls, for bilinear reading: the lower and upper pixel (clamped to the image) and the
// weight of the upper one. Offsets are not integers on the diagonals, so the neighbour's
// position is rounded as a double at each coordinate, exactly as a per-pixel evaluation
// would; tables keep the floor calls out of the inner loops.
struct Taps {
  std::vector<int> low, high;
  std::vector<float> weight;
};

enum class Reading { pixel, contiguous, gathered };

Taps taps(double d, int margin, int size) {
  Taps t;
  const auto count = static_cast<std::size_t>(std::max(size - 2 * margin, 0));
  t.low.resize(count), t.high.resize(count), t.weight.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double at = static_cast<int>(i) + margin + d;
    const int low = static_cast<int>(std::floor(at));
    t.low[i] = low;
    t.high[i] = std::min(low + 1, size - 1);
    t.weight[i] = static_cast<float>(at - low);
  }
  return t;
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
  std::array<Taps, 8> across, down;
  for (int p = 0; p < 8; ++p) {
    across[static_cast<std::size_t>(p)] = taps(dx[static_cast<std::size_t>(p)], margin, grey.cols);
    down[static_cast<std::size_t>(p)] = taps(dy[static_cast<std::size_t>(p)], margin, grey.rows);
  }
  // The code of a pattern by its bits (bit p: neighbour p brighter): the number of ones
  // when the circle has at most two transitions between darker and brighter, else 9.
  std::array<int, 256> code{};
  for (int bits = 0; bits < 256; ++bits) {
    int ones = 0, transitions = 0;
    for (int p = 0; p < 8; ++p) {
      ones += (bits >> p) & 1;
      transitions += ((bits >> p) & 1) != ((bits >> ((p + 1) % 8)) & 1) ? 1 : 0;
    }
    code[static_cast<std::size_t>(bits)] = transitions <= 2 ? ones : 9;
  }
  const int x_begin = margin, width = grey.cols - 2 * margin;
  if (width <= 0) {
    std::fill(bins, bins + kLbpBins, 0.0f);
    return;
  }
  // How each neighbour is read along a row (see rowValues): a pixel neighbour (integer
  // offsets) is the pixel itself when the image is finite, since the interpolation's zero
  // weights then add nothing; a neighbour whose upper pixel is always the lower one's right
  // neighbour is interpolated from contiguous pixels, which the compiler vectorises; any
  // other (clamped at the border) is gathered through the tables.
  const bool finite = cv::checkRange(grey);
  std::array<int, 8> shift{};
  std::array<Reading, 8> reading{};
  for (std::size_t p = 0; p < 8; ++p) {
    const Taps& t = across[p];
    shift[p] = t.low[0] - x_begin;
    bool contiguous = true;
    for (std::size_t i = 0; i < t.low.size() && contiguous; ++i) {
      contiguous = t.low[i] == static_cast<int>(i) + x_begin + shift[p] && t.high[i] == t.low[i] + 1;
    }
    const bool pixel = dx[p] == std::floor(dx[p]) && dy[p] == std::floor(dy[p]);
    reading[p] = pixel && finite ? Reading::pixel : contiguous ? Reading::contiguous : Reading::gathered;
  }
  std::vector<float> value(static_cast<std::size_t>(width)), threshold(static_cast<std::size_t>(width));
  std::vector<int> bits(static_cast<std::size_t>(width));
  for (int y = margin; y < grey.rows - margin; ++y) {
    const unsigned char* m = mask.ptr<unsigned char>(y) + x_begin;
    const float* g = grey.ptr<float>(y) + x_begin;
    const auto iy = static_cast<std::size_t>(y - margin);
    for (int i = 0; i < width; ++i) threshold[static_cast<std::size_t>(i)] = g[i] * (1.0f + kRelativeMargin);
    std::fill(bits.begin(), bits.end(), 0);
    for (std::size_t p = 0; p < 8; ++p) {
      const float* r0 = grey.ptr<float>(down[p].low[iy]);
      const float* r1 = grey.ptr<float>(down[p].high[iy]);
      const float fy = down[p].weight[iy];
      float* v = value.data();
      const float* fx = across[p].weight.data();
      switch (reading[p]) {
        case Reading::pixel: {
          const float* r = r0 + x_begin + shift[p];
          for (int i = 0; i < width; ++i) v[i] = r[i];
          break;
        }
        case Reading::contiguous: {
          // The same expression, in the same order, as plain bilinear interpolation.
          const float* a0 = r0 + x_begin + shift[p];
          const float* a1 = r1 + x_begin + shift[p];
          for (int i = 0; i < width; ++i) {
            v[i] = (1 - fy) * ((1 - fx[i]) * a0[i] + fx[i] * a0[i + 1]) +
                   fy * ((1 - fx[i]) * a1[i] + fx[i] * a1[i + 1]);
          }
          break;
        }
        case Reading::gathered: {
          const int* x0 = across[p].low.data();
          const int* x1 = across[p].high.data();
          for (int i = 0; i < width; ++i) {
            v[i] = (1 - fy) * ((1 - fx[i]) * r0[x0[i]] + fx[i] * r0[x1[i]]) +
                   fy * ((1 - fx[i]) * r1[x0[i]] + fx[i] * r1[x1[i]]);
          }
          break;
        }
      }
      const int bit = 1 << p;
      const float* t = threshold.data();
      int* b = bits.data();
      for (int i = 0; i < width; ++i) b[i] |= v[i] > t[i] ? bit : 0;
    }
    for (int i = 0; i < width; ++i) {
      if (!m[i]) continue;
      const int pattern = bits[static_cast<std::size_t>(i)];
      count[static_cast<std::size_t>(code[static_cast<std::size_t>(pattern)])] += 1.0;
      total += 1.0;
    }
  }
  for (int b = 0; b < kLbpBins; ++b) bins[b] = total > 0.0 ? static_cast<float>(count[b] / total) : 0.0f;
}

}  // namespace room_reverb::core::material_detail
