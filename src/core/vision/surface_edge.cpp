#include "surface_edge.h"

#include <algorithm>
#include <cmath>

namespace room_reverb::core::layout {

namespace {

// The farthest point of a surface without a step: the farthest before the first stretch
// of kGapShare of its distance (at least kMinGapM) that holds no point. A stray ranged far
// beyond the surface (a mismatch at the rim of a far wall) is no part of it: the ground of
// a rendered courtyard ends 13 m from the rig and six stray voxels lie at 26-27 m.
double reachBeforeGap(const std::vector<double>& count, const std::vector<double>& distances, double bin_m) {
  constexpr double kGapShare = 0.1;
  constexpr double kMinGapM = 1.0;
  std::vector<double> sorted = distances;
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  std::size_t last = static_cast<std::size_t>(std::max(0.0, *middle) / bin_m);
  for (std::size_t b = last; b < count.size(); ++b) {
    if (count[b] > 0.0) {
      last = b;
    } else if (static_cast<double>(b - last) * bin_m >= std::max(kMinGapM, kGapShare * static_cast<double>(last) * bin_m)) {
      break;
    }
  }
  double reach = 0.0;
  const double end = static_cast<double>(last + 1) * bin_m;
  for (double d : distances) {
    if (d < end) reach = std::max(reach, d);
  }
  return reach;
}

}  // namespace

std::optional<SurfaceEdge> surfaceEdge(const std::vector<double>& distances, double bin_m, double step_span_m,
                                  std::size_t min_points) {
  if (distances.size() < min_points) return std::nullopt;
  const double far = *std::max_element(distances.begin(), distances.end());
  const auto bins = static_cast<std::size_t>(far / bin_m) + 2;
  std::vector<double> count(bins, 0.0);
  for (double d : distances) count[static_cast<std::size_t>(std::max(0.0, d) / bin_m)] += 1.0;
  // The typical level: the count of the bin holding the median point, bins sorted by
  // count (a long sparse tail of strays beyond the wall, many bins with few points, cannot
  // pull it down as it would the median of the bins).
  std::vector<double> sorted = count;
  std::sort(sorted.begin(), sorted.end());
  double level = sorted.back(), below = 0.0;
  for (double c : sorted) {
    below += c;
    if (below >= 0.5 * static_cast<double>(distances.size())) {
      level = c;
      break;
    }
  }
  // A step: the mean over step_span_m inside a bin boundary at least kStepRatio times the
  // mean over step_span_m outside it, with the inside still a surface (a fraction of the
  // level; far away a surface thins out gradually as the rays spread, which is no step).
  // The edge is the innermost step beyond which the density never comes back to half of
  // what it was inside: a light's shadow on the ceiling is a step the ceiling comes back
  // from; a facade seen through a window, whose points rise to the ceiling's height beyond
  // the wall, and the strays beyond it are thin and end in steps of their own, further out.
  const auto span = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(step_span_m / bin_m)));
  std::vector<double> prefix(bins + 1, 0.0);
  for (std::size_t i = 0; i < bins; ++i) prefix[i + 1] = prefix[i] + count[i];
  const auto mean = [&](std::size_t from, std::size_t to) {  // bins [from, to)
    to = std::min(to, bins);
    return to > from ? (prefix[to] - prefix[from]) / static_cast<double>(to - from) : 0.0;
  };
  // The largest windowed mean from each bin outwards.
  std::vector<double> beyond_max(bins + 1, 0.0);
  for (std::size_t b = bins; b-- > 0;) beyond_max[b] = std::max(beyond_max[b + 1], mean(b, b + span));
  std::optional<std::size_t> edge_bin;
  for (std::size_t b = span; b < bins && !edge_bin; ++b) {
    const double inside = mean(b - span, b), outside = mean(b, b + span);
    if (inside >= kMinSurfaceLevel * level && outside * kStepRatio <= inside && beyond_max[b] < 0.5 * inside) {
      edge_bin = b;
    }
  }
  if (!edge_bin) return SurfaceEdge{reachBeforeGap(count, distances, bin_m), false};
  // Within the boundary's neighbourhood, the step's place from the filling of the two bins
  // around it: half of the inside level is where a blurred step is.
  const std::size_t b = *edge_bin;
  const double inside = mean(b - span, b);
  double edge = static_cast<double>(b) * bin_m;
  if (b >= 1 && count[b - 1] < 0.5 * inside) edge -= bin_m * (1.0 - count[b - 1] / inside);
  if (count[b] > 0.0) edge += bin_m * std::min(1.0, count[b] / inside);
  return SurfaceEdge{edge, true};
}

}  // namespace room_reverb::core::layout
