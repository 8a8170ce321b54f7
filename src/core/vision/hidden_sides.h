#pragma once
// The sides of a cuboid the rig cannot see, moved out as far as the observations allow.
//
// From one viewpoint a tall cabinet shows its front and perhaps one side; its back and the
// floor under a table are never seen. Fitting only the points would make every object as
// thin as its visible faces. Here each hidden side (its outward normal pointing away from
// the rig, and the bottom) is pushed out through the region behind it until rays from the
// rig to observed points cross that region: a ray that reached a point behind proves the
// space it passed through empty (space carving). What the rays cannot decide is decided
// by two priors: furniture square to the walls stands against a wall if nothing was seen
// between them (up to max_to_wall_m), and on the floor if nothing was seen beneath it. An
// object thinner than min_depth_m towards a hidden side (one face seen head-on) is
// deepened to it, as far as the rays allow.
#include <Eigen/Core>
#include <vector>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core::layout {

struct HiddenSideParams {
  Eigen::Vector3d rig_position = Eigen::Vector3d::Zero();  // room frame
  Eigen::Vector3d room_size = Eigen::Vector3d::Zero();
  double noise_fraction = 0.01;      // depth noise over range: observed points are trusted
  double noise_sigmas = 3.0;         //   only up to this many sigmas short of where they are
  double inset_m = 0.025;            // the carved region stays this far inside the box's other faces
  double max_to_wall_m = 1.0;        // a hidden side moves onto a wall at most this far away
  double min_depth_m = 0.4;          // a box thinner than this towards a hidden side is
                                     // deepened to it (as far as the rays allow)
  std::size_t free_rays = 5;         // rays that prove a region empty
};

// `observed`: room-frame points seen by the rig (voxel centroids), excluding the box's own.
// Moves the hidden sides of `box` (see above) and returns it.
CuboidObject extendHiddenSides(CuboidObject box, const std::vector<Eigen::Vector3d>& observed,
                               const HiddenSideParams& params);

// How many of the rig's rays to `observed` points (room frame) pass through the box's
// solid core (the box shrunk by the inset): each is a sighting through space the box
// claims is solid. A ray counts only up to its point's noise short of it.
std::size_t raysThroughBox(const CuboidObject& box, const std::vector<Eigen::Vector3d>& observed,
                           const HiddenSideParams& params);

}  // namespace room_reverb::core::layout
