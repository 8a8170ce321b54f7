#include "room_reverb/acoustics/cuboid.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/convex_polygons.h"

namespace room_reverb::core {

Eigen::Vector3d toCuboidFrame(const CuboidObject& cuboid, const Eigen::Vector3d& point) {
  const double c = std::cos(cuboid.yaw_rad), s = std::sin(cuboid.yaw_rad);
  const Eigen::Vector3d d = point - cuboid.center_m;
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z()};
}

Eigen::Vector3d fromCuboidFrame(const CuboidObject& cuboid, const Eigen::Vector3d& local) {
  const double c = std::cos(cuboid.yaw_rad), s = std::sin(cuboid.yaw_rad);
  return cuboid.center_m + Eigen::Vector3d(c * local.x() - s * local.y(), s * local.x() + c * local.y(), local.z());
}

bool cuboidContains(const CuboidObject& cuboid, const Eigen::Vector3d& point) {
  return (toCuboidFrame(cuboid, point).cwiseAbs().array() < 0.5 * cuboid.size_m.array()).all();
}

double distanceToCuboid(const CuboidObject& cuboid, const Eigen::Vector3d& point) {
  const Eigen::Vector3d outside = toCuboidFrame(cuboid, point).cwiseAbs() - 0.5 * cuboid.size_m;
  return outside.cwiseMax(0.0).norm();
}

std::array<Eigen::Vector2d, 4> cuboidFootprint(const CuboidObject& cuboid) {
  const Eigen::Vector2d c = cuboid.center_m.head<2>();
  const Eigen::Vector2d u(std::cos(cuboid.yaw_rad), std::sin(cuboid.yaw_rad));
  const Eigen::Vector2d v(-u.y(), u.x());
  const Eigen::Vector2d hx = 0.5 * cuboid.size_m.x() * u;
  const Eigen::Vector2d hy = 0.5 * cuboid.size_m.y() * v;
  return {c - hx - hy, c + hx - hy, c + hx + hy, c - hx + hy};
}

double cuboidOverlapM3(const CuboidObject& a, const CuboidObject& b) {
  const double z_overlap = std::min(a.center_m.z() + 0.5 * a.size_m.z(), b.center_m.z() + 0.5 * b.size_m.z()) -
                           std::max(a.center_m.z() - 0.5 * a.size_m.z(), b.center_m.z() - 0.5 * b.size_m.z());
  if (!(z_overlap > 0.0)) return 0.0;
  const auto fa = cuboidFootprint(a);
  const auto fb = cuboidFootprint(b);
  return z_overlap * polygonArea(clipToConvex({fa.begin(), fa.end()}, {fb.begin(), fb.end()}));
}

}  // namespace room_reverb::core
