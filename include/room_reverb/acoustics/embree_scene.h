#pragma once
// A triangle mesh in an Embree 3 BVH, for the ray queries of the image-source method and
// the ray tracer. Queries are const and safe to call from many threads at once.
#include <Eigen/Core>
#include <limits>
#include <memory>

#include "room_reverb/acoustics/triangle_mesh.h"

namespace room_reverb::core {

struct RayHit {
  bool hit = false;
  double distance_m = std::numeric_limits<double>::infinity();
  std::size_t triangle = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit geometric normal of the triangle
};

class EmbreeScene {
 public:
  // Builds the BVHs (single precision, as Embree stores them): a watertight one and one
  // built for speed (intersectFast), each about as large as the other. The mesh is
  // validated first.
  explicit EmbreeScene(TriangleMesh mesh);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  const TriangleMesh& mesh() const { return mesh_; }

  // Nearest hit along origin + t * direction for t in (t_near, t_far).
  RayHit intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                   double t_near = 1e-6,
                   double t_far = std::numeric_limits<double>::infinity()) const;
  // The same (t_far infinite) from a BVH built for speed, for the ray tracer: the
  // Möller-Trumbore test, about 8 % quicker over BRAS CR2's 43 million reflections than
  // the watertight test (Embree's robust mode) that intersect() and occluded() use, but
  // a ray that meets the shared edge of two triangles may slip between them. A ray that
  // finds nothing is asked again of the watertight BVH, so a ray that slips out of a
  // closed room still reflects where it should (CR2: 4 of 43 million); one that slips into
  // a closed object stays inside it, where its energy is lost to the room.
  RayHit intersectFast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_near = 1e-6) const;
  // True when something lies strictly between `from` and `to` (ends excluded by `margin_m`).
  bool occluded(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double margin_m = 1e-5) const;

  // Axis-aligned bounds of the mesh.
  Eigen::Vector3d boundsMin() const { return bounds_min_; }
  Eigen::Vector3d boundsMax() const { return bounds_max_; }

 private:
  struct Handles;
  TriangleMesh mesh_;
  std::unique_ptr<Handles> handles_;
  std::vector<Eigen::Vector3d> normals_;
  Eigen::Vector3d bounds_min_, bounds_max_;
};

}  // namespace room_reverb::core
