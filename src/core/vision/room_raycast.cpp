#include "room_reverb/vision/room_raycast.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace room_reverb::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

int indexOf(const std::vector<std::string>& names, const std::string& name) {
  return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
}

// The texture coordinates of a point on a face with normal along `axis`: the two other
// coordinates, the vertical one (z) second on vertical faces, so brick courses and tile
// rows run level.
void faceCoordinates(int axis, const Eigen::Vector3d& p, double& s, double& t) {
  switch (axis) {
    case 0: s = p.y(); t = p.z(); break;
    case 1: s = p.x(); t = p.z(); break;
    default: s = p.x(); t = p.y(); break;
  }
}

// The box face (kRoomSurfaceNames index) on axis `axis`, high side or low side.
int boxFace(int axis, bool high) {
  static constexpr int kFaces[3][2] = {{2, 3}, {4, 5}, {0, 1}};
  return kFaces[axis][high ? 1 : 0];
}

// The inside of the box: the ray leaves through the face whose plane it reaches first.
SurfaceHit boxExit(const CaptureGeometry& geometry, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  SurfaceHit hit;
  double best = kInf;
  int best_axis = 2;
  bool best_high = true;
  for (int axis = 0; axis < 3; ++axis) {
    const double d = direction[axis];
    if (d == 0.0) continue;
    const bool high = d > 0.0;
    const double t = ((high ? geometry.size_m[axis] : 0.0) - origin[axis]) / d;
    if (t < best) {
      best = t;
      best_axis = axis;
      best_high = high;
    }
  }
  const int face = boxFace(best_axis, best_high);
  hit.sky = face == 1 && !geometry.has_ceiling;
  if (!hit.sky) {
    hit.distance_m = best;
    hit.object_id = static_cast<std::uint16_t>(face);
    hit.material = geometry.face_material[static_cast<std::size_t>(face)];
    hit.normal = Eigen::Vector3d::Zero();
    hit.normal[best_axis] = best_high ? -1.0 : 1.0;
    hit.point_m = origin + best * direction;
    faceCoordinates(best_axis, hit.point_m, hit.s_m, hit.t_m);
  }
  return hit;
}

// Object k against the nearest hit so far: a hit nearer than it (or than the open sky) wins.
void hitObject(const CaptureGeometry& geometry, std::size_t k, const Eigen::Vector3d& origin,
               const Eigen::Vector3d& direction, SurfaceHit& hit) {
  const CaptureCuboid& cuboid = geometry.objects[k];
  const Eigen::Vector3d o = cuboid.local_to_room.transpose() * (origin - cuboid.center_m);
  const Eigen::Vector3d d = cuboid.local_to_room.transpose() * direction;
  double t_near = -kInf, t_far = kInf;
  int near_axis = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double h = cuboid.half_size_m[axis];
    if (d[axis] == 0.0) {
      if (std::abs(o[axis]) > h) t_far = -kInf;  // parallel to and outside this slab
      continue;
    }
    double t0 = (-h - o[axis]) / d[axis], t1 = (h - o[axis]) / d[axis];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) {
      t_near = t0;
      near_axis = axis;
    }
    t_far = std::min(t_far, t1);
  }
  const bool hit_object = t_near <= t_far && t_near > 0.0 && (hit.sky || t_near < hit.distance_m);
  if (!hit_object) return;
  hit.sky = false;
  hit.distance_m = t_near;
  hit.point_m = origin + t_near * direction;
  hit.object_id = static_cast<std::uint16_t>(6 + k);
  // Entering through the face the ray meets first: the one facing against the ray.
  const bool positive_side = d[near_axis] < 0.0;
  hit.face = 2 * near_axis + (positive_side ? 1 : 0);
  hit.material = cuboid.material;
  Eigen::Vector3d local_normal = Eigen::Vector3d::Zero();
  local_normal[near_axis] = positive_side ? 1.0 : -1.0;
  hit.normal = cuboid.local_to_room * local_normal;
  // Coordinates from the cuboid's corner, so they do not depend on where it stands.
  const Eigen::Vector3d local = o + t_near * d + cuboid.half_size_m;
  faceCoordinates(near_axis, local, hit.s_m, hit.t_m);
}

}  // namespace

CaptureGeometry makeCaptureGeometry(const RoomModel& room, const std::vector<std::string>& material_names) {
  CaptureGeometry geometry;
  geometry.size_m = room.size_m;
  geometry.has_ceiling = room.has_ceiling;
  for (std::size_t f = 0; f < kRoomSurfaceNames.size(); ++f) {
    const auto it = room.surfaces.find(kRoomSurfaceNames[f]);
    geometry.face_material[f] = it == room.surfaces.end() ? 0 : indexOf(material_names, it->second.material);
  }
  for (const CuboidObject& object : room.objects) {
    CaptureCuboid cuboid;
    cuboid.center_m = object.center_m;
    cuboid.half_size_m = 0.5 * object.size_m;
    cuboid.local_to_room = Eigen::AngleAxisd(object.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    cuboid.material = indexOf(material_names, object.material);
    geometry.objects.push_back(cuboid);
  }
  return geometry;
}

std::vector<std::size_t> objectsInReach(const CaptureGeometry& geometry, const Eigen::Vector3d& origin,
                                        const Eigen::Vector3d& centre, double radius_m, double beyond_m) {
  // A ray to a point P of the ball (range |P - origin| >= distance - radius) ends, beyond_m
  // past P, at most mu = (distance + radius + beyond_m) / (distance - radius) times the way
  // to P, so every point of it lies within mu * radius of the segment origin -> origin +
  // mu * (centre - origin). An object whose bounding sphere stays clear of that is out of
  // reach. A ball that comes too close to the origin for the bound keeps every object.
  std::vector<std::size_t> out;
  const Eigen::Vector3d axis = centre - origin;
  const double distance = axis.norm();
  const bool near = distance < 2.0 * radius_m;
  const double mu = near ? 0.0 : (distance + radius_m + beyond_m) / (distance - radius_m);
  for (std::size_t k = 0; k < geometry.objects.size(); ++k) {
    const CaptureCuboid& cuboid = geometry.objects[k];
    bool keep = near;
    if (!keep) {
      const Eigen::Vector3d w = cuboid.center_m - origin;
      const double along = std::clamp(w.dot(axis) / (distance * distance), 0.0, mu);
      // A millimetre for the rounding of the slab test.
      keep = (w - along * axis).norm() <= cuboid.half_size_m.norm() + mu * radius_m + 1e-3;
    }
    if (keep) out.push_back(k);
  }
  return out;
}

bool insideCuboid(const CaptureCuboid& cuboid, const Eigen::Vector3d& point, double margin_m) {
  const Eigen::Vector3d local = cuboid.local_to_room.transpose() * (point - cuboid.center_m);
  return (local.array().abs() < cuboid.half_size_m.array() + margin_m).all();
}

SurfaceHit castRay(const CaptureGeometry& geometry, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  SurfaceHit hit = boxExit(geometry, origin, direction);
  for (std::size_t k = 0; k < geometry.objects.size(); ++k) hitObject(geometry, k, origin, direction, hit);
  return hit;
}

SurfaceHit castRay(const CaptureGeometry& geometry, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                   const std::vector<std::size_t>& candidates) {
  SurfaceHit hit = boxExit(geometry, origin, direction);
  for (const std::size_t k : candidates) hitObject(geometry, k, origin, direction, hit);
  return hit;
}

}  // namespace room_reverb::core
