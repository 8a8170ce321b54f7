#pragma once
// Overlap of two cuboids that stand upright (rotated about z only), as the room model's
// objects do.
#include <Eigen/Core>
#include <array>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core {

// The four corners of a cuboid's footprint in the horizontal plane, counter-clockwise.
std::array<Eigen::Vector2d, 4> cuboidFootprint(const CuboidObject& box);

// Intersection volume over union volume, exact: the two footprint rectangles are clipped
// against each other (convex polygon clipping) and the area of the overlap is multiplied
// by the overlap of the two height intervals. 0 for disjoint boxes and when both boxes
// have zero volume. Throws InputError for a non-finite centre, size or yaw, or a negative
// size.
double orientedBoxIoU3d(const CuboidObject& a, const CuboidObject& b);

}  // namespace room_reverb::core
