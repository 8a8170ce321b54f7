#pragma once
// Exact ray casting in a room model: a ray from inside the room box against the inside of
// the box and against oriented cuboids (analytic slab tests; a handful of boxes does not
// need a BVH). The surface patches use it to keep only what the camera sees; the capture
// generator (synthetic_capture/) renders with it. Hits carry what the renderer and the
// truth images need.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core {

struct CaptureCuboid {
  Eigen::Vector3d center_m;
  Eigen::Vector3d half_size_m;
  Eigen::Matrix3d local_to_room;  // yaw about z
  int material = 0;               // index into the capture's material list
};

struct CaptureGeometry {
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();
  bool has_ceiling = true;
  std::array<int, 6> face_material{};  // kRoomSurfaceNames order; unused for an open ceiling
  std::vector<CaptureCuboid> objects;
};

struct SurfaceHit {
  bool sky = true;                        // nothing hit: the ray leaves through an open top
  double distance_m = 0.0;                // along the unit ray
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();  // room frame
  std::uint16_t object_id = 0;            // 0..5 box faces, 6 + k objects
  int face = 0;                           // for objects: 2 * axis + (positive side), for the salt
  int material = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, facing the space the ray came from
  double s_m = 0.0, t_m = 0.0;            // 2D surface coordinates (t vertical on vertical faces)
};

// The geometry of a room; material indices come from `material_index` (one per surface
// and object material name).
CaptureGeometry makeCaptureGeometry(const RoomModel& room, const std::vector<std::string>& material_names);

// `direction` must be unit length; `origin` inside the box.
SurfaceHit castRay(const CaptureGeometry& geometry, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

// The same, testing only the objects listed in `candidates` (indices into
// geometry.objects, ascending, so ties resolve as above). It returns what the full cast
// does whenever the ray misses every object left out, or meets them only beyond the
// nearest hit: a caller that culls the objects no ray of a bundle can reach (the surface
// patches do) sees no difference.
SurfaceHit castRay(const CaptureGeometry& geometry, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                   const std::vector<std::size_t>& candidates);

// The objects (ascending indices into geometry.objects) that a ray from `origin` towards
// a point P within radius_m of `centre` can meet no farther than beyond_m past P: a
// conservative cull (bounding spheres) for casting a bundle of rays at a patch of surface.
// Every object such a ray meets within that stretch is listed; others may be.
std::vector<std::size_t> objectsInReach(const CaptureGeometry& geometry, const Eigen::Vector3d& origin,
                                        const Eigen::Vector3d& centre, double radius_m, double beyond_m);

// True when the point lies strictly inside the cuboid (with a margin in metres).
bool insideCuboid(const CaptureCuboid& cuboid, const Eigen::Vector3d& point, double margin_m = 0.0);

}  // namespace room_reverb::core
