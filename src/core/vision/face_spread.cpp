#include "face_spread.h"

#include <algorithm>
#include <utility>

namespace room_reverb::core::layout {

namespace {

constexpr double kHalfNormalMedian = 0.6745;  // median of |x| for x ~ N(0, 1)
constexpr double kWindowHalfWidths = 4.0;

// The weighted median of (value, weight) pairs with values in (0, `window`], to a
// 4096th of the window (a tenth of a millimetre on a wall's 0.4 m window): from a
// histogram in linear time, where sorting a wall's hundreds of thousands of points took a
// tenth of the courtyard's layout. 0 if empty.
double weightedMedian(const std::vector<std::pair<double, double>>& samples, double window) {
  constexpr std::size_t kBins = 4096;
  if (samples.empty() || !(window > 0.0)) return 0.0;
  std::vector<double> mass(kBins, 0.0);
  double total = 0.0;
  for (const auto& [value, weight] : samples) {
    mass[std::min(kBins - 1, static_cast<std::size_t>(value / window * kBins))] += weight;
    total += weight;
  }
  double below = 0.0;
  for (std::size_t b = 0; b < kBins; ++b) {
    if (below + mass[b] >= 0.5 * total) {
      // Within the bin, in proportion to the mass still wanted.
      const double fraction = mass[b] > 0.0 ? (0.5 * total - below) / mass[b] : 0.5;
      return (static_cast<double>(b) + fraction) * window / kBins;
    }
    below += mass[b];
  }
  return window;
}

}  // namespace

std::array<double, 6> measuredFaceSpreads(const std::vector<WeightedPoint>& raw, const AlignedBox& box,
                                          const PlaneSpread& spread) {
  std::array<std::vector<std::pair<double, double>>, 6> beyond;
  std::array<double, 6> lo{}, hi{}, window{};
  for (int face = 0; face < 6; ++face) window[face] = kWindowHalfWidths * box.margin(face, spread);
  // Each axis's extent clear of its two faces: a face's points must lie within the
  // other axes' extents, so the corners (where the faces across meet it) stay out.
  for (int axis = 0; axis < 3; ++axis) {
    const int face_lo = axis == 2 ? 0 : 2 + 2 * axis, face_hi = face_lo + 1;
    lo[axis] = box.facePosition(face_lo) + box.margin(face_lo, spread);
    hi[axis] = box.facePosition(face_hi) - box.margin(face_hi, spread);
  }
  for (const WeightedPoint& r : raw) {
    for (int face = 0; face < 6; ++face) {
      if (face == 1 && !box.has_ceiling) continue;
      const int axis = face < 2 ? 2 : (face - 2) / 2;
      bool within = true;
      for (int other = 0; other < 3 && within; ++other) {
        within = other == axis || (r.p[other] > lo[other] && r.p[other] < hi[other]);
      }
      if (!within) continue;
      const bool low_side = face % 2 == 0;
      const double out = low_side ? box.facePosition(face) - r.p[axis] : r.p[axis] - box.facePosition(face);
      if (out > 0.0 && out <= window[face]) beyond[face].emplace_back(out, r.weight);
    }
  }
  std::array<double, 6> sigma{};
  for (int face = 0; face < 6; ++face) sigma[face] = weightedMedian(beyond[face], window[face]) / kHalfNormalMedian;
  return sigma;
}

}  // namespace room_reverb::core::layout
