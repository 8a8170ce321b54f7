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
#include <cstdint>
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

// The rig's lines of sight to observed points (room frame, voxel centroids), each ending
// its point's noise short of the point (only that stretch is known to be empty), sorted
// by azimuth. A box's tests below visit only the lines whose azimuth falls within the
// box's (its region's) footprint as seen from the rig: a line outside it cannot cross
// the region. A room holds hundreds of thousands of lines and a piece of furniture
// subtends a few degrees, so this skips most of them; the result is that of testing all.
class SightLines {
 public:
  SightLines() = default;
  // One line per observed point, in their order (line i ends short of point i).
  SightLines(const std::vector<Eigen::Vector3d>& observed, const HiddenSideParams& params);

  std::size_t size() const { return ends_.size(); }
  const Eigen::Vector3d& end(std::size_t i) const { return ends_[i]; }
  // The lines that may cross the vertical prism over a convex footprint (room-frame plan
  // corners, counter-clockwise): all of them if the rig stands over it or on its edge.
  void linesOver(const std::vector<Eigen::Vector2d>& footprint, std::vector<std::uint32_t>& out) const;

 private:
  Eigen::Vector3d rig_ = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> ends_;
  std::vector<std::uint32_t> by_azimuth_;   // the lines that prove anything, bin by bin
  std::vector<std::uint32_t> bin_start_;    // where each azimuth bin starts in by_azimuth_, and the end
};

// Which lines belong to the box being tested (its own points prove nothing about it):
// those whose owner (one per line, e.g. its voxel's cluster) is `a` or `b`.
struct OwnLines {
  const std::vector<std::int32_t>* owner = nullptr;
  std::int32_t a = -1, b = -1;
  bool contains(std::size_t i) const {
    return owner != nullptr && ((*owner)[i] == a || (*owner)[i] == b);
  }
};

// Moves the hidden sides of `box` (see above) against the lines of sight other than its
// own, and returns it.
CuboidObject extendHiddenSides(CuboidObject box, const SightLines& lines, const OwnLines& own,
                               const HiddenSideParams& params);

// How many lines of sight (other than the box's own) pass through the box's solid core
// (the box shrunk by the inset): each is a sighting through space the box claims is
// solid.
std::size_t raysThroughBox(const CuboidObject& box, const SightLines& lines, const OwnLines& own,
                           const HiddenSideParams& params);

}  // namespace room_reverb::core::layout
