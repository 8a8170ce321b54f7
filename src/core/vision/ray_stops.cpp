#include "ray_stops.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace room_reverb::core::layout {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kStepM = 0.05;     // distances past the edge
constexpr double kLateralStepM = 0.1;
constexpr std::size_t kMinStops = 20;

}  // namespace

RayStops::RayStops(const std::vector<WeightedPoint>& points, double cell_deg)
    : cell_rad_(cell_deg * kPi / 180.0),
      azimuth_cells_(static_cast<std::size_t>(std::ceil(2.0 * kPi / cell_rad_))),
      elevation_cells_(static_cast<std::size_t>(std::ceil(kPi / cell_rad_))),
      nearest_(azimuth_cells_ * elevation_cells_, Eigen::Vector3f::Zero()),
      range_(azimuth_cells_ * elevation_cells_, std::numeric_limits<float>::infinity()) {
  for (const WeightedPoint& w : points) {
    const float range = w.p.norm();
    if (!(range > 0.0f)) continue;
    const std::size_t c = cell(w.p.cast<double>());
    if (range < range_[c]) range_[c] = range, nearest_[c] = w.p;
  }
}

std::size_t RayStops::cell(const Eigen::Vector3d& d) const {
  const double azimuth = std::atan2(d.y(), d.x()) + kPi;                // [0, 2 pi]
  const double elevation = std::atan2(d.z(), d.head<2>().norm()) + 0.5 * kPi;  // [0, pi]
  const auto a = std::min(azimuth_cells_ - 1, static_cast<std::size_t>(azimuth / cell_rad_));
  const auto e = std::min(elevation_cells_ - 1, static_cast<std::size_t>(elevation / cell_rad_));
  return e * azimuth_cells_ + a;
}

std::optional<Eigen::Vector3f> RayStops::along(const Eigen::Vector3d& target) const {
  const std::size_t c = cell(target);
  if (!std::isfinite(range_[c])) return std::nullopt;
  return nearest_[c];
}

std::optional<double> wallWhereCeilingRaysStop(const RayStops& stops, int axis, bool below, double edge,
                                               double ceiling_z, const std::pair<double, double>& lateral,
                                               double tolerance, double reach_m, double max_beyond_m) {
  const double sign = below ? -1.0 : 1.0;
  const double margin = 0.1 * (lateral.second - lateral.first);
  const double from = lateral.first + margin, to = lateral.second - margin;
  if (!(to > from) || !(reach_m > 0.0)) return std::nullopt;
  // Windows of reach_m / 2 from reach_m / 2 past the edge outwards: a window whose rays
  // mostly come back with nothing, or on the ceiling where they were aimed, is still over
  // the unranged ceiling, and the next one further out is asked.
  for (double near = 0.5 * reach_m; near + 0.5 * reach_m <= max_beyond_m + 1e-9; near += 0.5 * reach_m) {
    int aimed = 0;
    std::vector<double> stop_points;
    for (double d = edge + near; d <= edge + near + 0.5 * reach_m; d += kStepM) {
      for (double l = from; l <= to; l += kLateralStepM) {
        Eigen::Vector3d target;
        target[axis] = sign * d;
        target[1 - axis] = l;
        target.z() = ceiling_z;
        ++aimed;
        const std::optional<Eigen::Vector3f> hit = stops.along(target);
        if (!hit) continue;
        // A stop further inside than the edge is something in the room in front of the
        // wall (furniture, a hanging light): no evidence of where the wall is.
        const double at = sign * static_cast<double>((*hit)[axis]);
        if (at > edge - tolerance && at < d - tolerance) stop_points.push_back(at);
      }
    }
    // Enough stops (furniture in front of the wall returns nothing: its points are the
    // objects', not the structure's), and on one surface: half of them within twice the
    // tolerance of their median (a far wall's stops spread by 0.2-0.3 m either side of it
    // at 6 m through the stereo of a 1024-pixel pair).
    if (stop_points.size() < std::max<std::size_t>(kMinStops, static_cast<std::size_t>(aimed) / 4)) continue;
    const auto middle = stop_points.begin() + static_cast<std::ptrdiff_t>(stop_points.size() / 2);
    std::nth_element(stop_points.begin(), middle, stop_points.end());
    const double wall = *middle;
    const auto on_it = std::count_if(stop_points.begin(), stop_points.end(),
                                     [&](double at) { return std::abs(at - wall) <= 2.0 * tolerance; });
    if (2 * static_cast<std::size_t>(on_it) < stop_points.size() || wall <= edge + tolerance) return std::nullopt;
    return wall;
  }
  return std::nullopt;
}

}  // namespace room_reverb::core::layout
