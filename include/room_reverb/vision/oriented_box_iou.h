#pragma once
// Overlap of two cuboids that stand upright (rotated about z only), as the room model's
// objects do.
#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core {

// Intersection volume (cuboidOverlapM3, exact) over union volume. 0 for disjoint boxes
// and when both boxes have zero volume. Throws InputError for a non-finite centre, size or
// yaw, or a negative size.
double orientedBoxIoU3d(const CuboidObject& a, const CuboidObject& b);

}  // namespace room_reverb::core
