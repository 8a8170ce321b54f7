#pragma once
// One furniture cluster as an upright cuboid in the room frame.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core::layout {

struct CuboidFitParams {
  Eigen::Vector3d room_size = Eigen::Vector3d::Zero();
  // How far from each face of the room (kRoomSurfaceNames order) points were cut away as
  // belonging to that face: a cluster reaching the cut was cut by it.
  std::array<double, 6> face_margin{};
  double extent_quantile = 0.01;       // extents from these quantiles, not min/max: stereo strays
  double manhattan_snap_rad = 0.0873;  // 5 degrees
  double manhattan_tolerance = 0.05;   // see fitCuboid
  double closeness_floor_m = 0.03;     // distances below this count as this; see fitCuboid
  Eigen::Vector3d rig_position = Eigen::Vector3d::Zero();  // room frame
  double noise_fraction = 0.01;        // depth noise over range
  double contact_m = 0.1;              // beyond the cut, a face this close to a room face touches it
};

// The cuboid of a cluster's points (room frame).
//
// Yaw: the one at which the points hug the sides of their rectangle most closely (the
// closeness criterion of L-shape fitting, Zhang et al. 2017, "Efficient L-shape fitting
// for vehicle detection using laser scanners"), searched every 2 degrees, then to 0.25.
// Not the smallest rectangle: an object seen from one side shows an L of two faces, whose
// smallest rectangle lies as well along the L's hypotenuse as along its sides; the faces
// lie on the sides only at the right yaw. Distances below the points' depth noise (at
// the cluster's range, but at least closeness_floor_m) count as that noise, lest the
// score follow the noise of a face seen head-on. Snapped to the walls' directions if
// within manhattan_snap_rad, or if the score square to the walls is within
// manhattan_tolerance of the best (most furniture stands square to the walls; a poorly
// seen object decides nothing).
//
// Extents between the extent quantiles, each side pulled in by one sigma of the depth
// noise along its axis (the noise pushes quantiles out). Then faces are moved onto the
// room faces they touch: the bottom onto the floor (the points near the floor were cut
// with the floor), the top onto the ceiling, and, for a cuboid square to the walls, a
// side onto a wall it reaches (its back was cut with the wall). Normalised (below).
// Label, material and confidence are left to the caller.
CuboidObject fitCuboid(const std::vector<Eigen::Vector3d>& points, const CuboidFitParams& params);

// The same cuboid with size.x >= size.y and yaw in (-pi/2, pi/2], so equal boxes compare equal.
CuboidObject normalisedCuboid(CuboidObject box);

}  // namespace room_reverb::core::layout
