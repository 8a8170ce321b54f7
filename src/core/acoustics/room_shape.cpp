#include "room_reverb/acoustics/room_shape.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/convex_polygons.h"

namespace room_reverb::core {

bool RoomShape::inBox(const Eigen::Vector3d& point) const {
  return (point.array() > 0.0).all() && (point.array() < size_m.array()).all();
}

std::optional<std::size_t> RoomShape::objectContaining(const Eigen::Vector3d& point) const {
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (cuboidContains(objects[i], point)) return i;
  }
  return std::nullopt;
}

double RoomShape::freeVolumeM3() const {
  // Objects stand upright, so within a slab between consecutive top and bottom heights the
  // set of objects present is constant and the solid is a prism over their united
  // footprints.
  std::vector<double> heights = {0.0, size_m.z()};
  for (const CuboidObject& object : objects) {
    for (double z : {object.center_m.z() - 0.5 * object.size_m.z(), object.center_m.z() + 0.5 * object.size_m.z()}) {
      heights.push_back(std::clamp(z, 0.0, size_m.z()));
    }
  }
  std::sort(heights.begin(), heights.end());
  heights.erase(std::unique(heights.begin(), heights.end()), heights.end());

  const Polygon2d floor = {{0.0, 0.0}, {size_m.x(), 0.0}, {size_m.x(), size_m.y()}, {0.0, size_m.y()}};
  double solid_m3 = 0.0;
  for (std::size_t k = 0; k + 1 < heights.size(); ++k) {
    const double middle = 0.5 * (heights[k] + heights[k + 1]);
    std::vector<Polygon2d> footprints;
    for (const CuboidObject& object : objects) {
      if (std::abs(middle - object.center_m.z()) >= 0.5 * object.size_m.z()) continue;
      const auto corners = cuboidFootprint(object);
      Polygon2d inside = clipToConvex({corners.begin(), corners.end()}, floor);
      if (polygonArea(inside) > 0.0) footprints.push_back(std::move(inside));
    }
    if (!footprints.empty()) solid_m3 += (heights[k + 1] - heights[k]) * unionArea(footprints);
  }
  return size_m.prod() - solid_m3;
}

}  // namespace room_reverb::core
