#pragma once
// The solids of a room built from a room model: a box [0, size] (open at the top when it
// has no ceiling) and upright cuboid objects, which may touch the box and each other,
// overlap each other or stick out through a wall. Whether a point is in free air is
// decided from these solids, not by crossing parity on their triangles: parity needs every
// face to be a crossing between inside and outside, which faces that coincide (an object
// flush with a wall or the floor, two objects side by side) or solids that overlap are not.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "room_reverb/acoustics/cuboid.h"

namespace room_reverb::core {

struct RoomShape {
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();
  bool has_ceiling = true;
  std::vector<CuboidObject> objects;

  // Strictly inside the box: 0 < p < size along every axis (below the top of the walls
  // when the room has no ceiling).
  bool inBox(const Eigen::Vector3d& point) const;
  // The lowest index of an object whose interior holds `point`.
  std::optional<std::size_t> objectContaining(const Eigen::Vector3d& point) const;
  // The box's volume less that of the objects' union inside it, exact however they touch,
  // overlap or stick out: slab by slab in height, the footprints of the objects present,
  // clipped to the box's, are united.
  double freeVolumeM3() const;
};

}  // namespace room_reverb::core
