#include "room_reverb/vision/oriented_box_iou.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

namespace {

void checkBox(const CuboidObject& box, const char* which) {
  if (!box.center_m.allFinite() || !box.size_m.allFinite() || !std::isfinite(box.yaw_rad)) {
    throw InputError(std::string("orientedBoxIoU3d: box ") + which + " has a non-finite centre, size or yaw");
  }
  if ((box.size_m.array() < 0.0).any()) {
    throw InputError(std::string("orientedBoxIoU3d: box ") + which + " has a negative size");
  }
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double polygonArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) twice += cross2(polygon[i], polygon[(i + 1) % polygon.size()]);
  return 0.5 * std::abs(twice);
}

// Sutherland-Hodgman: keeps the part of `subject` on the left of every edge of the convex,
// counter-clockwise `clip`. Exact for convex polygons, which rectangles are.
std::vector<Eigen::Vector2d> clipConvex(std::vector<Eigen::Vector2d> subject,
                                        const std::array<Eigen::Vector2d, 4>& clip) {
  for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const Eigen::Vector2d& a = clip[e];
    const Eigen::Vector2d edge = clip[(e + 1) % clip.size()] - a;
    std::vector<Eigen::Vector2d> kept;
    kept.reserve(subject.size() + 4);
    for (std::size_t i = 0; i < subject.size(); ++i) {
      const Eigen::Vector2d& p = subject[i];
      const Eigen::Vector2d& q = subject[(i + 1) % subject.size()];
      const double side_p = cross2(edge, p - a);
      const double side_q = cross2(edge, q - a);
      if (side_p >= 0.0) kept.push_back(p);
      // An edge crossing the clip line contributes its crossing point.
      if ((side_p >= 0.0) != (side_q >= 0.0)) kept.push_back(p + (q - p) * (side_p / (side_p - side_q)));
    }
    subject = std::move(kept);
  }
  return subject;
}

}  // namespace

std::array<Eigen::Vector2d, 4> cuboidFootprint(const CuboidObject& box) {
  const Eigen::Vector2d c = box.center_m.head<2>();
  const Eigen::Vector2d u(std::cos(box.yaw_rad), std::sin(box.yaw_rad));
  const Eigen::Vector2d v(-u.y(), u.x());
  const Eigen::Vector2d hx = 0.5 * box.size_m.x() * u;
  const Eigen::Vector2d hy = 0.5 * box.size_m.y() * v;
  return {c - hx - hy, c + hx - hy, c + hx + hy, c - hx + hy};
}

double orientedBoxIoU3d(const CuboidObject& a, const CuboidObject& b) {
  checkBox(a, "a");
  checkBox(b, "b");
  const double volume_a = a.size_m.prod();
  const double volume_b = b.size_m.prod();
  const double z_overlap = std::min(a.center_m.z() + 0.5 * a.size_m.z(), b.center_m.z() + 0.5 * b.size_m.z()) -
                           std::max(a.center_m.z() - 0.5 * a.size_m.z(), b.center_m.z() - 0.5 * b.size_m.z());
  if (z_overlap <= 0.0 || volume_a + volume_b <= 0.0) return 0.0;
  const auto fa = cuboidFootprint(a);
  const auto fb = cuboidFootprint(b);
  const double area = polygonArea(clipConvex({fa.begin(), fa.end()}, fb));
  const double intersection = area * z_overlap;
  const double union_volume = volume_a + volume_b - intersection;
  if (union_volume <= 0.0) return 0.0;
  // Rounding in the clipping may push a perfect overlap a hair past 1.
  return std::clamp(intersection / union_volume, 0.0, 1.0);
}

}  // namespace room_reverb::core
