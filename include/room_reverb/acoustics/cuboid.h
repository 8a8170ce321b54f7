#pragma once
// A room model's object: a labelled cuboid standing upright (turned about z only), and
// where a point is relative to it.
#include <Eigen/Core>
#include <array>
#include <string>

#include "room_reverb/acoustics/material.h"

namespace room_reverb::core {

struct CuboidObject {
  std::string label;
  std::string material;
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();  // extent along its own x, y, z
  double yaw_rad = 0.0;                              // rotation about z
  double confidence = 1.0;
  // Optional, as SurfaceAssignment's (room_model.h): the second choice of material and
  // its confidence; not simulated.
  std::string runner_up{};
  double runner_up_confidence = 0.0;
  // As SurfaceAssignment's (room_model.h): the scattering the object's relief adds (what
  // its box does not follow: shelves' contents, the gap under a worktop, a table's chairs
  // held in one box), per octave band 63 Hz-16 kHz. Zero: a plain box.
  OctaveBandValues relief_scattering{};
};

// `point` in the cuboid's own frame: origin at its centre, axes along its sides.
Eigen::Vector3d toCuboidFrame(const CuboidObject& cuboid, const Eigen::Vector3d& point);
// Back from the cuboid's own frame to the room's.
Eigen::Vector3d fromCuboidFrame(const CuboidObject& cuboid, const Eigen::Vector3d& local);

// Strictly inside: a point on a face is not, so that solids that touch leave their common
// face to neither.
bool cuboidContains(const CuboidObject& cuboid, const Eigen::Vector3d& point);

// Distance (m) from `point` to the solid cuboid, 0 inside.
double distanceToCuboid(const CuboidObject& cuboid, const Eigen::Vector3d& point);

// The four corners of the cuboid's footprint in the horizontal plane, counter-clockwise.
std::array<Eigen::Vector2d, 4> cuboidFootprint(const CuboidObject& cuboid);

// Volume (m^3) the two cuboids share, exact: the overlap of their footprints (convex
// polygon clipping) times the overlap of their height intervals.
double cuboidOverlapM3(const CuboidObject& a, const CuboidObject& b);

}  // namespace room_reverb::core
