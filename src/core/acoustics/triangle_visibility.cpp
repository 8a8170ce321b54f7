#include "room_reverb/acoustics/triangle_visibility.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace room_reverb::core {
namespace {

// Projections closer than this (m) count as touching, not overlapping.
constexpr double kTouchM = 1e-7;

template <std::size_t N>
void project(const std::array<Eigen::Vector3d, N>& points, const Eigen::Vector3d& axis, double& lo, double& hi) {
  lo = hi = axis.dot(points[0]);
  for (std::size_t i = 1; i < N; ++i) {
    const double p = axis.dot(points[i]);
    lo = std::min(lo, p);
    hi = std::max(hi, p);
  }
}

// Whether the tetrahedron and the triangle overlap by more than touching: two convex
// polytopes are apart exactly when one of their face normals or one cross product of an
// edge of each separates them.
bool overlaps(const std::array<Eigen::Vector3d, 4>& tetra, const std::array<Eigen::Vector3d, 3>& tri) {
  std::array<Eigen::Vector3d, 6> tetra_edges = {tetra[1] - tetra[0], tetra[2] - tetra[0], tetra[3] - tetra[0],
                                                tetra[2] - tetra[1], tetra[3] - tetra[2], tetra[1] - tetra[3]};
  std::array<Eigen::Vector3d, 3> tri_edges = {tri[1] - tri[0], tri[2] - tri[1], tri[0] - tri[2]};
  std::array<Eigen::Vector3d, 5 + 18> axes;
  std::size_t n = 0;
  axes[n++] = tetra_edges[0].cross(tetra_edges[1]);  // faces (0 1 2), (0 2 3), (0 3 1), (1 2 3)
  axes[n++] = tetra_edges[1].cross(tetra_edges[2]);
  axes[n++] = tetra_edges[2].cross(tetra_edges[0]);
  axes[n++] = tetra_edges[3].cross(tetra_edges[4]);
  axes[n++] = tri_edges[0].cross(tri_edges[1]);
  for (const Eigen::Vector3d& a : tetra_edges) {
    for (const Eigen::Vector3d& b : tri_edges) axes[n++] = a.cross(b);
  }
  for (const Eigen::Vector3d& raw : axes) {
    const double length = raw.norm();
    if (!(length > 1e-12)) continue;  // parallel edges: no axis
    const Eigen::Vector3d axis = raw / length;
    double tetra_lo, tetra_hi, tri_lo, tri_hi;
    project(tetra, axis, tetra_lo, tetra_hi);
    project(tri, axis, tri_lo, tri_hi);
    if (tetra_hi <= tri_lo + kTouchM || tri_hi <= tetra_lo + kTouchM) return false;
  }
  return true;
}

}  // namespace

std::vector<bool> trianglesSeenWhole(const TriangleMesh& mesh, const Eigen::Vector3d& point, std::size_t max_triangles) {
  const std::size_t count = mesh.triangleCount();
  std::vector<bool> seen(count, false);
  if (count > max_triangles) return seen;
  std::vector<std::array<Eigen::Vector3d, 3>> corners(count);
  std::vector<Eigen::AlignedBox3d> boxes(count);
  for (std::size_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) {
      corners[t][k] = mesh.vertices[mesh.triangles[t][k]];
      boxes[t].extend(corners[t][k]);
    }
  }
  for (std::size_t t = 0; t < count; ++t) {
    const Eigen::Vector3d normal = mesh.normal(t);
    if (!(std::abs(normal.dot(point - corners[t][0])) >= 1e-6)) continue;  // in its plane
    const std::array<Eigen::Vector3d, 4> pyramid = {point, corners[t][0], corners[t][1], corners[t][2]};
    Eigen::AlignedBox3d pyramid_box = boxes[t];
    pyramid_box.extend(point);
    bool hidden = false;
    for (std::size_t other = 0; other < count && !hidden; ++other) {
      if (other == t || !pyramid_box.intersects(boxes[other])) continue;
      hidden = overlaps(pyramid, corners[other]);
    }
    seen[t] = !hidden;
  }
  return seen;
}

}  // namespace room_reverb::core
