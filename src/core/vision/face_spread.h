#pragma once
// How thick each face of the fitted room box looks in the cloud.
//
// The layout options carry one depth noise for the whole cloud (a calibration), but
// stereo noise differs from face to face and from capture to capture: a plain wall
// matches worse than a textured one, a smaller image is noisier everywhere. Cutting the
// furniture away from a face by the calibrated margin alone leaves the tail of a noisy
// face's points in the room, where they join the furniture standing near it. The face's
// own points tell how thick it is: the part of its spread beyond it (outside the room)
// holds only noise and a few strays, while the part in front also holds whatever stands
// near the face, so only the far side is measured.
#include <array>
#include <vector>

#include "room_box_fit.h"

namespace room_reverb::core::layout {

// Per face (kRoomSurfaceNames order): the 1-sigma spread [m] of the raw points (aligned
// frame) along the face's normal, from the weighted median of their distances beyond the
// face (the median of a half-normal is 0.674 sigma), counting the points within the
// face's extent (clear of the faces across it by their margins) and at most four nominal
// half widths beyond it (farther ones are strays or seen through a window). 0 for a face
// with no points beyond it, and for the ceiling of a room without one.
std::array<double, 6> measuredFaceSpreads(const std::vector<WeightedPoint>& raw, const AlignedBox& box,
                                          const PlaneSpread& spread);

}  // namespace room_reverb::core::layout
