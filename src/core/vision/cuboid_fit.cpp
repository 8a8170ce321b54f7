#include "cuboid_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace room_reverb::core::layout {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

struct Interval {
  double lo = 0.0, hi = 0.0;
};

// The [q, 1 - q] quantile range of `values` (reordered).
Interval quantileRange(std::vector<double>& values, double q) {
  const auto n = static_cast<std::ptrdiff_t>(values.size());
  const auto lo_at = std::clamp<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(q * static_cast<double>(n)), 0, n - 1);
  const auto hi_at = std::clamp<std::ptrdiff_t>(n - 1 - lo_at, 0, n - 1);
  std::nth_element(values.begin(), values.begin() + lo_at, values.end());
  const double lo = values[static_cast<std::size_t>(lo_at)];
  std::nth_element(values.begin(), values.begin() + hi_at, values.end());
  return {lo, values[static_cast<std::size_t>(hi_at)]};
}

// The points' plan coordinates along (cos yaw, sin yaw) and (-sin yaw, cos yaw).
void project(const std::vector<Eigen::Vector3d>& points, double yaw, std::vector<double>& u, std::vector<double>& v) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  u.clear(), v.clear();
  for (const auto& p : points) u.push_back(c * p.x() + s * p.y()), v.push_back(-s * p.x() + c * p.y());
}

// Per axis, the side the points are nearer to overall (sum of squared distances); each
// point scores one over its distance to the nearer of those two sides, at least `floor`.
double closeness(const std::vector<Eigen::Vector3d>& points, double yaw, double floor, const CuboidFitParams& params,
                 std::vector<double>& u, std::vector<double>& v, std::vector<double>& scratch) {
  project(points, yaw, u, v);
  scratch = u;
  const Interval eu = quantileRange(scratch, params.extent_quantile);
  scratch = v;
  const Interval ev = quantileRange(scratch, params.extent_quantile);
  double u_lo = 0.0, u_hi = 0.0, v_lo = 0.0, v_hi = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    u_lo += (u[i] - eu.lo) * (u[i] - eu.lo), u_hi += (eu.hi - u[i]) * (eu.hi - u[i]);
    v_lo += (v[i] - ev.lo) * (v[i] - ev.lo), v_hi += (ev.hi - v[i]) * (ev.hi - v[i]);
  }
  const double u_side = u_lo < u_hi ? eu.lo : eu.hi;
  const double v_side = v_lo < v_hi ? ev.lo : ev.hi;
  double score = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    const double d = std::min(std::abs(u[i] - u_side), std::abs(v[i] - v_side));
    score += 1.0 / std::max(d, floor);
  }
  return score;
}

double wrapQuarter(double a) { return a - 0.5 * kPi * std::floor((a + 0.25 * kPi) / (0.5 * kPi)); }

}  // namespace

CuboidObject fitCuboid(const std::vector<Eigen::Vector3d>& points, const CuboidFitParams& params) {
  std::vector<double> u, v, scratch;
  // The yaw search looks at a thinned copy: a few thousand points fix a rectangle.
  std::vector<Eigen::Vector3d> thinned;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 3000);
  for (std::size_t i = 0; i < points.size(); i += stride) thinned.push_back(points[i]);

  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : thinned) centroid += p;
  centroid /= static_cast<double>(std::max<std::size_t>(1, thinned.size()));
  const double floor =
      std::max(params.closeness_floor_m, params.noise_fraction * (centroid - params.rig_position).norm());
  const auto score = [&](double yaw) { return closeness(thinned, yaw, floor, params, u, v, scratch); };
  double best_yaw = 0.0, best = -std::numeric_limits<double>::infinity();
  for (double yaw = -45.0 * kDeg; yaw < 45.0 * kDeg; yaw += 2.0 * kDeg) {
    const double s = score(yaw);
    if (s > best) best = s, best_yaw = yaw;
  }
  const double coarse = best_yaw;
  for (double yaw = coarse - 2.0 * kDeg; yaw <= coarse + 2.0 * kDeg; yaw += 0.25 * kDeg) {
    const double s = score(yaw);
    if (s > best) best = s, best_yaw = yaw;
  }
  best_yaw = wrapQuarter(best_yaw);
  const bool square_to_walls = std::abs(best_yaw) <= params.manhattan_snap_rad ||
                               score(0.0) >= (1.0 - params.manhattan_tolerance) * best;
  if (square_to_walls) best_yaw = 0.0;

  project(points, best_yaw, u, v);
  Interval eu = quantileRange(u, params.extent_quantile);
  Interval ev = quantileRange(v, params.extent_quantile);
  scratch.clear();
  for (const auto& p : points) scratch.push_back(p.z());
  Interval z = quantileRange(scratch, params.extent_quantile);
  // Depth noise pushes the quantiles out: by 2.3 sigma for a face seen head-on, by about
  // 1 sigma for the edge of a surface seen at a slant. Each side is pulled in by one
  // sigma of the noise along its axis (at most a quarter of the extent).
  {
    const Eigen::Vector3d view = centroid - params.rig_position;
    const double cy = std::cos(best_yaw), sy = std::sin(best_yaw);
    const double range = view.norm();
    const Eigen::Vector3d dir = range > 0.0 ? Eigen::Vector3d(view / range) : Eigen::Vector3d::Zero();
    const auto pullIn = [&](Interval& e, double cosine) {
      const double sigma = std::min(params.noise_fraction * range * std::abs(cosine), 0.25 * (e.hi - e.lo));
      e.lo += sigma, e.hi -= sigma;
    };
    pullIn(eu, cy * dir.x() + sy * dir.y());
    pullIn(ev, -sy * dir.x() + cy * dir.y());
    pullIn(z, dir.z());
  }

  const Eigen::Vector3d& room = params.room_size;
  const auto& cut = params.face_margin;
  const double reach = params.contact_m;
  if (z.lo <= cut[0] + reach) z.lo = 0.0;
  if (z.hi >= room.z() - cut[1] - reach) z.hi = room.z();
  if (square_to_walls) {
    if (eu.lo <= cut[2] + reach) eu.lo = 0.0;
    if (eu.hi >= room.x() - cut[3] - reach) eu.hi = room.x();
    if (ev.lo <= cut[4] + reach) ev.lo = 0.0;
    if (ev.hi >= room.y() - cut[5] - reach) ev.hi = room.y();
  }

  CuboidObject box;
  const double c = std::cos(best_yaw), s = std::sin(best_yaw);
  const double mu = 0.5 * (eu.lo + eu.hi), mv = 0.5 * (ev.lo + ev.hi);
  box.center_m = Eigen::Vector3d(c * mu - s * mv, s * mu + c * mv, 0.5 * (z.lo + z.hi));
  box.size_m = Eigen::Vector3d(eu.hi - eu.lo, ev.hi - ev.lo, z.hi - z.lo);
  box.yaw_rad = best_yaw;
  return normalisedCuboid(box);
}

CuboidObject normalisedCuboid(CuboidObject box) {
  if (box.size_m.x() < box.size_m.y()) {
    std::swap(box.size_m.x(), box.size_m.y());
    box.yaw_rad += 0.5 * kPi;
  }
  box.yaw_rad = std::remainder(box.yaw_rad, kPi);  // [-pi/2, pi/2]
  if (box.yaw_rad <= -0.5 * kPi) box.yaw_rad += kPi;
  return box;
}

}  // namespace room_reverb::core::layout
