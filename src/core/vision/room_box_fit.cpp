#include "room_box_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "ray_stops.h"
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

namespace {

// The strict rule, for a side without a horizontal surface's edge: see findWallPair.
std::optional<WallChoice> wallByRays(const std::vector<PlanePeak>& peaks, const PlaneHistogram& rays,
                                     const BoxFitParams& params, bool below) {
  const double far = 1e6;  // beyond any coordinate (max_range_m bounds them)
  const double best = strongest(peaks, below);
  std::vector<const PlanePeak*> candidates;
  for (const PlanePeak& p : peaks) {
    if ((p.position_m < 0.0) == below && p.support >= params.outer_plane_fraction * best &&
        p.contrast >= params.min_plane_contrast) {
      candidates.push_back(&p);
    }
  }
  if (candidates.empty()) return std::nullopt;
  // Inner to outer.
  std::sort(candidates.begin(), candidates.end(), [](const PlanePeak* a, const PlanePeak* b) {
    return std::abs(a->position_m) < std::abs(b->position_m);
  });
  const PlanePeak* chosen = candidates.back();
  for (const PlanePeak* p : candidates) {
    const double half = params.spread.halfWidth(p->position_m);
    const double on = rays.count(p->position_m - half, p->position_m + half);
    const double beyond = below ? rays.count(-far, p->position_m - half) : rays.count(p->position_m + half, far);
    if (on >= beyond) {
      chosen = p;
      break;
    }
  }
  return WallChoice{chosen->position_m, WallBasis::kPlane, 0.6, chosen->contrast};
}

// No plane where the surface ends, `edge` from the rig. Under a ceiling that is a wall
// hidden by furniture or clutter; where only the ground ends with no plane standing there
// (the walls across reach that far, but they make no plane along this axis), an open side.
WallChoice wallAtSurfaceEnd(bool below, double edge, bool edge_from_ceiling) {
  const double sign = below ? -1.0 : 1.0;
  if (!edge_from_ceiling) return {sign * edge, WallBasis::kOpen, 0.3, 0.0};
  return {sign * edge, WallBasis::kEdge, 0.4, 0.0};
}

// How much of the room's length along the wall (`from` to `to`) a plane's voxels cover:
// the fraction of 0.2 m stretches holding any of them. Covered, not spanned: the walls
// across reach into any plane's window at the two ends, and the end of a wall across
// looks like a faint plane of its own.
double lateralCoverage(const WallBand& band, double position, double half_width, double from, double to) {
  constexpr double kStretchM = 0.2;
  const auto stretches = static_cast<std::size_t>(std::max(1.0, std::ceil((to - from) / kStretchM)));
  std::vector<bool> covered(stretches, false);
  for (std::size_t i = 0; i < band.coordinate.size(); ++i) {
    const double l = band.lateral[i];
    if (std::abs(band.coordinate[i] - position) > half_width || l < from || l >= to) continue;
    covered[std::min(stretches - 1, static_cast<std::size_t>((l - from) / kStretchM))] = true;
  }
  return static_cast<double>(std::count(covered.begin(), covered.end(), true)) / static_cast<double>(stretches);
}

// The room's extent along the walls of a band: the 1st and 99th percentiles of the
// lateral coordinate (selected, not sorted: the band holds every wall voxel).
std::pair<double, double> lateralExtent(const WallBand& band) {
  if (band.lateral.empty()) return {0.0, 0.0};
  std::vector<double> values = band.lateral;
  const auto at = [&](std::size_t k) {
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    return values[k];
  };
  const double from = at(values.size() / 100);
  return {from, at(values.size() * 99 / 100)};
}

// The rule with the ceiling's or floor's edge `edge` (a distance): see findWallPair.
// `extent` is the band's lateralExtent.
WallChoice wallAtEdge(const std::vector<PlanePeak>& peaks, const WallBand& band, const std::pair<double, double>& extent,
                      const BoxFitParams& params, bool below, double edge, bool edge_from_ceiling) {
  const double tolerance = std::max(params.edge_tolerance_m, params.spread.halfWidth(edge));
  const auto [from, to] = extent;
  // This side's layers with how much of the room's length each covers; a faint layer
  // counts only where it runs along a good part of the room.
  std::vector<std::pair<const PlanePeak*, double>> layers;
  double edge_coverage = 0.0, edge_support = 0.0;  // the most any layer at the edge covers, and holds
  for (const PlanePeak& p : peaks) {
    if ((p.position_m < 0.0) != below) continue;
    const double coverage = lateralCoverage(band, p.position_m, params.spread.halfWidth(p.position_m), from, to);
    if (p.contrast < params.min_plane_contrast && coverage < params.min_layer_coverage) continue;
    layers.emplace_back(&p, coverage);
    if (std::abs(std::abs(p.position_m) - edge) <= tolerance) {
      edge_coverage = std::max(edge_coverage, coverage);
      edge_support = std::max(edge_support, p.support);
    }
  }
  // A layer near the edge; or one a little beyond it, where wall units or a wardrobe
  // reaching the ceiling end the ceiling in front of the wall: the wall shows along the
  // run (between worktop and units, past its ends), as much of the room's length as the
  // units' fronts at the edge. A recess's back (a door's, a window's) beyond the wall that
  // ends the ceiling shows only across the opening, and a facade through a window only
  // across the window: a layer beyond the edge covering less than kBeyondCoverageShare of
  // what the edge's layer covers is neither. Nor is a sparse one (strays and range noise
  // beyond the wall) holding less than kBeyondSupportShare of the edge layer's points.
  // (In cluttered rooms 161-200, looked at for this rule: recess backs cover 0.27-0.47 of
  // the edge layer's length, the walls behind units 1.15 of it with 0.71 of its points,
  // stray layers 0.03 of its points.)
  // With no layer at the edge only a dense plane beyond it counts.
  constexpr double kBeyondCoverageShare = 0.75;
  constexpr double kBeyondSupportShare = 0.25;
  std::vector<const PlanePeak*> candidates;
  for (const auto& [p, coverage] : layers) {
    const double beyond = std::abs(p->position_m) - edge;
    const bool dense = p->contrast >= params.min_plane_contrast;
    if (beyond <= tolerance ||
        (beyond <= params.hidden_wall_m && (dense || edge_coverage > 0.0) &&
         coverage >= kBeyondCoverageShare * edge_coverage && p->support >= kBeyondSupportShare * edge_support)) {
      candidates.push_back(p);
    }
  }
  const PlanePeak* outermost = nullptr;
  for (const PlanePeak* p : candidates) {
    if (!outermost || std::abs(p->position_m) > std::abs(outermost->position_m)) outermost = p;
  }
  if (outermost && std::abs(outermost->position_m) >= edge - std::max(params.hidden_wall_m, tolerance)) {
    // The layers of one wall: of those within layer_gap_m of the outermost, the one with
    // the most area (the main wall plane, not the back of a door recess in it nor a
    // radiator in front of it).
    // A layer further inside the edge than its tolerance is not the wall: the ceiling goes
    // on past it (units or shelving along the whole wall, under a ceiling that ends at the
    // wall behind them).
    const PlanePeak* chosen = outermost;
    for (const PlanePeak* p : candidates) {
      const double at = std::abs(p->position_m);
      if (at >= std::abs(outermost->position_m) - params.layer_gap_m && at >= edge - tolerance && p->support > chosen->support) {
        chosen = p;
      }
    }
    const double confidence = chosen->contrast >= params.min_plane_contrast ? 0.9 : 0.75;
    return {chosen->position_m, WallBasis::kPlaneAtEdge, confidence, chosen->contrast};
  }
  return wallAtSurfaceEnd(below, edge, edge_from_ceiling);
}

// Where only the ground ends and no layer of the calibrated width stands there: a wall
// the stereo ranges far worse than the calibrated noise (a plain facade far away, whose
// few pixels of disparity carry little texture to match: a concrete wall 12.6 m from the
// rig scatters its points over 5-9 % of their range between quartiles, against the
// calibrated 1 % sigma) spreads over many of those windows, and none stands out from its
// flanks. An open side has nothing standing at the ground's end at any width. So the
// planes are sought again with the window widened kWidenings times, on the band's points
// away from the walls across (which run along the axis and would fill a wide window's
// flanks as much as the window). A plane so found scatters its foot over the ground as
// far as its window reaches, and the ground's edge with it: it may lie inside the edge by
// its own window and the calibrated tolerance. Of those covering at least
// min_layer_coverage of the room's length, the one of most support is the wall.
std::optional<WallChoice> scatteredWallAtEdge(const WallBand& band, const std::pair<double, double>& extent,
                                              const BoxFitParams& params, bool below, double edge) {
  constexpr std::array<double, 3> kWidenings = {2.0, 4.0, 8.0};
  constexpr double kAcrossShare = 0.1;  // of the room's length at either end: the walls across
  const double length = extent.second - extent.first;
  std::vector<double> inner;
  for (std::size_t i = 0; i < band.coordinate.size(); ++i) {
    const double l = band.lateral[i];
    if (l > extent.first + kAcrossShare * length && l < extent.second - kAcrossShare * length) {
      inner.push_back(band.coordinate[i]);
    }
  }
  if (inner.empty()) return std::nullopt;
  const PlaneHistogram histogram(inner, params.bin_m);
  const double tolerance = std::max(params.edge_tolerance_m, params.spread.halfWidth(edge));
  for (double widen : kWidenings) {
    PlaneSpread wide = params.spread;
    wide.noise_fraction *= widen;
    wide.min_half_width_m *= widen;
    const PlanePeak* best = nullptr;
    const auto peaks = histogram.peaks(wide, params.min_plane_support, params.min_plane_contrast);
    for (const PlanePeak& p : peaks) {
      const double at = std::abs(p.position_m);
      if ((p.position_m < 0.0) != below || at > edge + tolerance || at < edge - tolerance - wide.halfWidth(at)) continue;
      if (lateralCoverage(band, p.position_m, wide.halfWidth(at), extent.first, extent.second) <
          params.min_layer_coverage) {
        continue;
      }
      if (!best || p.support > best->support) best = &p;
    }
    if (best) return WallChoice{best->position_m, WallBasis::kScatteredPlane, 0.4, best->contrast};
  }
  return std::nullopt;
}

}  // namespace

WallPair findWallPair(const WallBand& band, const std::vector<double>& ray_coordinate,
                      const std::array<std::optional<SurfaceEdge>, 2>& edges, bool edge_from_ceiling,
                      const BoxFitParams& params, const char* axis) {
  const PlaneHistogram histogram(band.coordinate, params.bin_m);
  const auto peaks =
      histogram.peaks(params.spread, params.min_plane_support, std::min(params.min_layer_contrast, params.min_plane_contrast));
  const PlaneHistogram rays(ray_coordinate, params.bin_m);
  std::optional<std::pair<double, double>> extent;  // computed once, if a side needs it
  WallPair pair;
  for (int side = 0; side < 2; ++side) {
    const bool below = side == 0;
    std::optional<WallChoice> choice;
    const std::optional<SurfaceEdge>& edge = edges[static_cast<std::size_t>(side)];
    if (edge && edge->step) {
      if (!extent) extent = lateralExtent(band);
      choice = wallAtEdge(peaks, band, *extent, params, below, edge->distance_m, edge_from_ceiling);
    } else {
      choice = wallByRays(peaks, rays, params, below);
      if (!choice && edge) choice = wallAtSurfaceEnd(below, edge->distance_m, edge_from_ceiling);
    }
    if (choice && choice->basis == WallBasis::kOpen) {
      if (!extent) extent = lateralExtent(band);
      const auto scattered = scatteredWallAtEdge(band, *extent, params, below, edge->distance_m);
      if (scattered) choice = scattered;
    }
    if (!choice) {
      throw InputError(std::string("room layout: no wall found on the ") + (below ? "-" : "+") + axis +
                       " side of the rig (no dense vertical plane there, and no floor or ceiling reaching out "
                       "to one); the cloud must show the room around the rig");
    }
    (below ? pair.lo : pair.hi) = *choice;
  }
  return pair;
}

AlignedBox fitAlignedBox(const std::vector<Eigen::Vector3d>& voxels, const std::vector<WeightedPoint>& raw,
                         const HorizontalPlanes& planes, const BoxFitParams& params) {
  const PlaneSpread& spread = params.spread;
  const double band_lo = planes.floor_z + std::max(params.band_margin_m, spread.halfWidth(planes.floor_z));
  const double band_hi = planes.has_ceiling
                             ? planes.ceiling_z - std::max(params.band_margin_m, spread.halfWidth(planes.ceiling_z))
                             : std::numeric_limits<double>::infinity();
  WallBand along_x, along_y;
  std::vector<double> ray_xs, ray_ys;
  for (WallBand* band : {&along_x, &along_y}) band->z_lo = band_lo, band->z_hi = band_hi;
  for (const auto& p : voxels) {
    if (p.z() <= band_lo || p.z() >= band_hi) continue;
    along_x.coordinate.push_back(p.x()), along_x.lateral.push_back(p.y()), along_x.height.push_back(p.z());
    along_y.coordinate.push_back(p.y()), along_y.lateral.push_back(p.x()), along_y.height.push_back(p.z());
  }
  for (const auto& r : raw) {
    if (r.p.z() > band_lo && r.p.z() < band_hi) ray_xs.push_back(r.p.x()), ray_ys.push_back(r.p.y());
  }
  // How far the ceiling (the floor in a room without one) reaches on each side, along each
  // axis. Not the floor where there is a ceiling: the floor runs on through doorways, and
  // furniture hides its edge more often than the ceiling's.
  std::array<std::array<std::optional<SurfaceEdge>, 2>, 2> edges{};
  for (int axis = 0; axis < 2; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? -1.0 : 1.0;
      std::optional<SurfaceEdge> reach;
      for (int surface = 0; surface < 2; ++surface) {
        if ((surface == 1) != planes.has_ceiling) continue;
        const double z = surface == 0 ? planes.floor_z : planes.ceiling_z;
        const double half = spread.halfWidth(z);
        std::vector<double> distances;
        for (const auto& p : voxels) {
          if (std::abs(p.z() - z) <= half && sign * p[axis] > 0.0) distances.push_back(sign * p[axis]);
        }
        reach = surfaceEdge(distances);
      }
      edges[static_cast<std::size_t>(axis)][static_cast<std::size_t>(side)] = reach;
    }
  }
  WallPair wx = findWallPair(along_x, ray_xs, edges[0], planes.has_ceiling, params, "x");
  WallPair wy = findWallPair(along_y, ray_ys, edges[1], planes.has_ceiling, params, "y");
  // A wall at the ceiling's edge with no plane there: the edge may be where the ceiling's
  // range ends rather than the ceiling (ray_stops.h).
  std::optional<RayStops> stops;  // made only when a wall needs it
  for (int axis = 0; axis < 2 && planes.has_ceiling; ++axis) {
    WallPair& pair = axis == 0 ? wx : wy;
    for (int side = 0; side < 2; ++side) {
      WallChoice& choice = side == 0 ? pair.lo : pair.hi;
      if (choice.basis != WallBasis::kEdge) continue;
      if (!stops) stops.emplace(raw);
      const double edge = std::abs(choice.position_m);
      const double tolerance = std::max(params.edge_tolerance_m, spread.halfWidth(edge));
      const std::optional<double> wall = wallWhereCeilingRaysStop(*stops, axis, side == 0, edge, planes.ceiling_z,
                                                                  lateralExtent(axis == 0 ? along_x : along_y), tolerance);
      if (wall) choice = {(side == 0 ? -1.0 : 1.0) * *wall, WallBasis::kRayStop, 0.5, 0.0};
    }
  }

  // A room open on one side (a courtyard, an open-plan room) is a room; a floor with
  // walls on two sides or none is not.
  std::string open_sides;
  int open = 0;
  const std::pair<const WallChoice*, const char*> sides[] = {{&wx.lo, "-x"}, {&wx.hi, "+x"}, {&wy.lo, "-y"}, {&wy.hi, "+y"}};
  for (const auto& [choice, name] : sides) {
    if (choice->basis != WallBasis::kOpen) continue;
    open_sides += (open++ == 0 ? "" : " and ") + std::string(name);
  }
  if (open >= 2) {
    throw InputError("room layout: no wall found on the " + open_sides +
                     " sides of the rig (nothing stands where the floor ends); a room needs walls on at least "
                     "three sides");
  }

  AlignedBox box;
  box.x_lo = wx.lo.position_m, box.x_hi = wx.hi.position_m, box.y_lo = wy.lo.position_m, box.y_hi = wy.hi.position_m;
  box.choice[2] = wx.lo, box.choice[3] = wx.hi, box.choice[4] = wy.lo, box.choice[5] = wy.hi;
  box.choice[0] = {planes.floor_z, WallBasis::kPlane, 0.9, 0.0};
  box.choice[1] = {planes.ceiling_z, WallBasis::kPlane, planes.has_ceiling ? 0.9 : 0.0, 0.0};
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
        // A wall placed at an edge has no plane of its own to refine on.
        const WallBasis basis = box.choice[static_cast<std::size_t>(face)].basis;
        if (basis == WallBasis::kEdge || basis == WallBasis::kOpen || basis == WallBasis::kRayStop) continue;
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
  for (int face = 0; face < 6; ++face) box.choice[static_cast<std::size_t>(face)].position_m = box.facePosition(face);
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
