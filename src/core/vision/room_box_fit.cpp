#include "room_box_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "room_reverb/common/error.h"

namespace room_reverb::core::layout {

namespace {

// Support of the strongest peak below (or above) the origin.
double strongest(const std::vector<PlanePeak>& peaks, bool below) {
  double best = 0.0;
  for (const PlanePeak& p : peaks) {
    if ((p.position_m < 0.0) == below) best = std::max(best, p.support);
  }
  return best;
}

// The outermost peak on one side of the origin with support >= fraction * that side's
// strongest; nullptr if the side has none.
const PlanePeak* outermost(const std::vector<PlanePeak>& peaks, bool below, double fraction) {
  const double best = strongest(peaks, below);
  const PlanePeak* chosen = nullptr;
  for (const PlanePeak& p : peaks) {
    if ((p.position_m < 0.0) != below || p.support < fraction * best) continue;
    if (!chosen || std::abs(p.position_m) > std::abs(chosen->position_m)) chosen = &p;
  }
  return chosen;
}

}  // namespace

HorizontalPlanes findHorizontalPlanes(const std::vector<double>& z, const BoxFitParams& params) {
  const PlaneHistogram histogram(z, params.bin_m);
  const auto peaks = histogram.peaks(params.spread, params.min_plane_support, params.min_plane_contrast);
  const PlanePeak* floor = outermost(peaks, true, params.outer_plane_fraction);
  if (!floor) {
    throw InputError(
        "room layout: no floor plane below the rig (no dense horizontal layer of points); the cloud "
        "must be in the levelled rig frame (z up, origin at the rig) and show the floor");
  }
  HorizontalPlanes planes;
  planes.floor_z = floor->position_m;
  planes.floor_support = floor->support;
  const PlanePeak* ceiling = outermost(peaks, false, params.outer_plane_fraction);
  if (ceiling && strongest(peaks, false) >= params.ceiling_min_support_fraction * floor->support) {
    planes.has_ceiling = true;
    planes.ceiling_z = ceiling->position_m;
    planes.ceiling_support = ceiling->support;
  }
  return planes;
}

WallPair findWallPair(const std::vector<double>& voxel_coordinate, const std::vector<double>& ray_coordinate,
                      const BoxFitParams& params, const char* axis) {
  const PlaneHistogram histogram(voxel_coordinate, params.bin_m);
  const auto peaks = histogram.peaks(params.spread, params.min_plane_support, params.min_plane_contrast);
  const PlaneHistogram rays(ray_coordinate, params.bin_m);
  const double far = 1e6;  // beyond any coordinate (max_range_m bounds them)
  const auto pick = [&](bool below) -> const PlanePeak* {
    const double best = strongest(peaks, below);
    std::vector<const PlanePeak*> candidates;
    for (const PlanePeak& p : peaks) {
      if ((p.position_m < 0.0) == below && p.support >= params.outer_plane_fraction * best) candidates.push_back(&p);
    }
    if (candidates.empty()) return nullptr;
    // Inner to outer.
    std::sort(candidates.begin(), candidates.end(), [](const PlanePeak* a, const PlanePeak* b) {
      return std::abs(a->position_m) < std::abs(b->position_m);
    });
    for (const PlanePeak* p : candidates) {
      const double half = params.spread.halfWidth(p->position_m);
      const double on = rays.count(p->position_m - half, p->position_m + half);
      const double beyond = below ? rays.count(-far, p->position_m - half) : rays.count(p->position_m + half, far);
      if (on >= beyond) return p;
    }
    return candidates.back();
  };
  const PlanePeak* lo = pick(true);
  const PlanePeak* hi = pick(false);
  if (!lo || !hi) {
    throw InputError(std::string("room layout: no wall found on the ") + (lo ? "+" : "-") + axis +
                     " side of the rig (no dense vertical plane there); the cloud must show a "
                     "four-walled room around the rig");
  }
  return {lo->position_m, hi->position_m};
}

double AlignedBox::facePosition(int face) const {
  switch (face) {
    case 0: return floor_z;
    case 1: return top_z;
    case 2: return x_lo;
    case 3: return x_hi;
    case 4: return y_lo;
    default: return y_hi;
  }
}

double AlignedBox::margin(int face, const PlaneSpread& spread) const { return spread.halfWidth(facePosition(face)); }

AlignedBox fitAlignedBox(const std::vector<Eigen::Vector3d>& voxels, const std::vector<WeightedPoint>& raw,
                         const HorizontalPlanes& planes, const BoxFitParams& params) {
  const PlaneSpread& spread = params.spread;
  const double band_lo = planes.floor_z + std::max(params.band_margin_m, spread.halfWidth(planes.floor_z));
  const double band_hi = planes.has_ceiling
                             ? planes.ceiling_z - std::max(params.band_margin_m, spread.halfWidth(planes.ceiling_z))
                             : std::numeric_limits<double>::infinity();
  std::vector<double> xs, ys, ray_xs, ray_ys;
  for (const auto& p : voxels) {
    if (p.z() > band_lo && p.z() < band_hi) xs.push_back(p.x()), ys.push_back(p.y());
  }
  for (const auto& r : raw) {
    if (r.p.z() > band_lo && r.p.z() < band_hi) ray_xs.push_back(r.p.x()), ray_ys.push_back(r.p.y());
  }
  const WallPair wx = findWallPair(xs, ray_xs, params, "x");
  const WallPair wy = findWallPair(ys, ray_ys, params, "y");

  AlignedBox box;
  box.x_lo = wx.lo, box.x_hi = wx.hi, box.y_lo = wy.lo, box.y_hi = wy.hi;
  box.floor_z = planes.floor_z;
  box.has_ceiling = planes.has_ceiling;
  box.top_z = planes.has_ceiling ? planes.ceiling_z : -std::numeric_limits<double>::infinity();
  if (!planes.has_ceiling) {
    for (const auto& p : voxels) box.top_z = std::max(box.top_z, p.z());
  }

  // Each wall from the band's points between the two walls across it; twice, because the
  // walls across move a little in the first pass.
  std::vector<double> values, weights;
  for (int pass = 0; pass < 2; ++pass) {
    for (int axis = 0; axis < 2; ++axis) {
      const int other = 1 - axis;
      const double other_lo = box.facePosition(2 + 2 * other) + box.margin(2 + 2 * other, spread);
      const double other_hi = box.facePosition(3 + 2 * other) - box.margin(3 + 2 * other, spread);
      values.clear(), weights.clear();
      for (const auto& r : raw) {
        if (r.p.z() > band_lo && r.p.z() < band_hi && r.p[other] > other_lo && r.p[other] < other_hi) {
          values.push_back(r.p[axis]), weights.push_back(r.weight);
        }
      }
      for (int side = 0; side < 2; ++side) {
        const int face = 2 + 2 * axis + side;
        double& position = axis == 0 ? (side == 0 ? box.x_lo : box.x_hi) : (side == 0 ? box.y_lo : box.y_hi);
        position = refinePlanePosition(values, weights, position, spread.halfWidth(position), &box.support[face]);
      }
    }
  }

  // Floor and ceiling from the points between the walls (the walls' feet and heads would
  // otherwise add a one-sided tail to the window).
  values.clear(), weights.clear();
  for (const auto& r : raw) {
    if (r.p.x() > box.x_lo + box.margin(2, spread) && r.p.x() < box.x_hi - box.margin(3, spread) &&
        r.p.y() > box.y_lo + box.margin(4, spread) && r.p.y() < box.y_hi - box.margin(5, spread)) {
      values.push_back(r.p.z()), weights.push_back(r.weight);
    }
  }
  box.floor_z = refinePlanePosition(values, weights, box.floor_z, spread.halfWidth(box.floor_z), &box.support[0]);
  if (box.has_ceiling) {
    box.top_z = refinePlanePosition(values, weights, box.top_z, spread.halfWidth(box.top_z), &box.support[1]);
  }
  return box;
}

double wallTopEdge(const std::vector<WeightedPoint>& raw, const AlignedBox& box, const PlaneSpread& spread) {
  std::vector<double> z, weight;
  for (const auto& r : raw) {
    bool on_wall = false;
    for (int face = 2; face < 6 && !on_wall; ++face) {
      const int axis = (face - 2) / 2, other = 1 - axis;
      on_wall = std::abs(r.p[axis] - box.facePosition(face)) <= box.margin(face, spread) &&
                r.p[other] > box.facePosition(2 + 2 * other) && r.p[other] < box.facePosition(3 + 2 * other);
    }
    if (on_wall) z.push_back(r.p.z()), weight.push_back(r.weight);
  }
  const double floor_z = box.floor_z;
  if (z.empty()) return floor_z;
  const double bin = 0.01;
  double top = -std::numeric_limits<double>::infinity();
  for (double v : z) top = std::max(top, v);
  const auto bins = static_cast<std::size_t>(std::max(1.0, std::ceil((top - floor_z) / bin))) + 1;
  std::vector<double> h(bins, 0.0);
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (z[i] < floor_z) continue;
    h[std::min(bins - 1, static_cast<std::size_t>((z[i] - floor_z) / bin))] += weight[i];
  }
  // Light smoothing (3 bins), then the level: the median bin of the walls' upper half
  // (furniture hides the lower part; the top bins are the edge itself).
  std::vector<double> s(bins, 0.0);
  for (std::size_t i = 0; i < bins; ++i) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t j = (i == 0 ? 0 : i - 1); j <= std::min(bins - 1, i + 1); ++j) sum += h[j], ++n;
    s[i] = sum / n;
  }
  // The 99th percentile of the weight as the provisional top, so a few stray points above
  // the walls do not stretch the plateau window into empty space.
  std::vector<double> cumulative(bins, 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < bins; ++i) total += h[i], cumulative[i] = total;
  std::size_t p99 = 0;
  while (p99 + 1 < bins && cumulative[p99] < 0.99 * total) ++p99;
  const std::size_t from = p99 / 2;
  const std::size_t to = p99 > 15 ? p99 - 15 : p99;
  std::vector<double> plateau(s.begin() + static_cast<std::ptrdiff_t>(from),
                              s.begin() + static_cast<std::ptrdiff_t>(std::max(from + 1, to)));
  std::nth_element(plateau.begin(), plateau.begin() + static_cast<std::ptrdiff_t>(plateau.size() / 2), plateau.end());
  const double half = 0.5 * plateau[plateau.size() / 2];
  // From the top down, the first bin at or above half the level; interpolate to the
  // crossing between it and the bin above.
  std::size_t i = bins - 1;
  while (i > 0 && s[i] < half) --i;
  double edge = (static_cast<double>(i) + 0.5) * bin;
  if (i + 1 < bins && s[i] > s[i + 1]) edge += bin * (s[i] - half) / (s[i] - s[i + 1]);
  return floor_z + edge;
}

}  // namespace room_reverb::core::layout
