#pragma once
// What a 360-degree depth camera at the rig sees of a RoomModel: rays in all directions
// from the rig, each ending at the first surface it meets (the box's inner faces or an
// object cuboid), so occlusion is as in a real capture. Range-proportional noise along the
// ray and strays beyond the walls imitate spherical stereo. Used as known truth by the
// room layout tests.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/vision/point_cloud.h"

namespace room_reverb::test {

// An opening in a wall through which the rig sees a facade outside: a plane parallel to
// the wall, facade_distance_m beyond it (a building across the street).
struct ScanWindow {
  int face = 3;                   // the wall, as an index into kRoomSurfaceNames (2..5)
  double from_m = 0.0, to_m = 0.0;  // extent along the wall (y for x walls, x for y walls)
  double bottom_m = 0.0, top_m = 0.0;  // heights above the floor
  double facade_distance_m = 3.0;
};

struct RoomScanOptions {
  std::size_t rays = 200000;           // directions, spread evenly over the sphere
  double range_noise_fraction = 0.015;  // 1-sigma depth noise over range, along the ray
  double stray_fraction = 0.03;         // fraction of rays whose point lies beyond the walls
  double stray_depth_m = 1.5;           // strays land up to this far beyond the box
  std::uint32_t seed = 1;
  bool hints = false;  // fill CloudPoint::hint from the truth (floor, ceiling, wall, object)
  double polar_cap_deg = 0.0;  // no points within this of the zenith and nadir (stereo on a
                               // vertical baseline cannot range there)
  std::vector<ScanWindow> windows;
};

struct RoomScan {
  core::PointCloud cloud;         // in the rig frame
  std::vector<int> face;          // per point: the box face hit (kRoomSurfaceNames index), or -1
  std::vector<int> object;        // per point: the object hit (index into model.objects), or -1
  std::vector<bool> stray;        // per point: placed beyond the walls on purpose, or seen through a window
};

// Options like a spherical stereo capture's: 300 000 rays, 1 % range noise (the layout
// fit's default), 3 % strays, no range within 10 degrees of the poles.
RoomScanOptions stereoLikeScanOptions(std::uint32_t seed);

// The rig pose is model.rig_position_m / rig_rotation. A room without a ceiling loses the
// rays that leave through the top. Objects are solid cuboids rotated by their yaw.
RoomScan scanRoomModel(const core::RoomModel& model, const RoomScanOptions& options = {});

// Distance along a unit ray (room frame) from a point inside the room to the first surface
// it meets; sets `face` (box face, or -1) and `object` (or -1). Infinity if the ray leaves
// through the open top of a room without a ceiling.
double castRoomRay(const core::RoomModel& model, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                   int* face, int* object);

}  // namespace room_reverb::test
