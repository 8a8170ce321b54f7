#include "room_reverb/acoustics/triangle_visibility.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace room_reverb::core {
namespace {

using Corners = std::array<Eigen::Vector3d, 3>;

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
bool overlaps(const std::array<Eigen::Vector3d, 4>& tetra, const Corners& tri) {
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
  for (const Eigen::Vector3d& axis : axes) {
    // Projections onto the axis unnormalised: lengths along it come scaled by its norm.
    const double length2 = axis.squaredNorm();
    if (!(length2 > 1e-24)) continue;  // parallel edges: no axis
    const double touch = kTouchM * std::sqrt(length2);
    double tetra_lo, tetra_hi, tri_lo, tri_hi;
    project(tetra, axis, tetra_lo, tetra_hi);
    project(tri, axis, tri_lo, tri_hi);
    if (tetra_hi <= tri_lo + touch || tri_hi <= tetra_lo + touch) return false;
  }
  return true;
}

// The four cells of a triangle cut at its edges' midpoints: at corners 0, 1 and 2, and
// the middle one (turned half a turn: its corner 0 is the midpoint opposite corner 0).
std::array<Corners, 4> quarters(const Corners& c) {
  const Eigen::Vector3d m01 = 0.5 * (c[0] + c[1]), m02 = 0.5 * (c[0] + c[2]), m12 = 0.5 * (c[1] + c[2]);
  return {Corners{c[0], m01, m02}, Corners{m01, c[1], m12}, Corners{m02, m12, c[2]}, Corners{m12, m02, m01}};
}

}  // namespace

TriangleVisibility::TriangleVisibility(const TriangleMesh& mesh, const Eigen::Vector3d& point, int depth,
                                       std::size_t max_triangles) {
  const std::size_t count = mesh.triangleCount();
  if (count > max_triangles) return;
  std::vector<Corners> corners(count);
  std::vector<Eigen::AlignedBox3d> boxes(count);
  for (std::size_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) {
      corners[t][k] = mesh.vertices[mesh.triangles[t][k]];
      boxes[t].extend(corners[t][k]);
    }
  }
  roots_.resize(count);
  frames_.resize(count);
  // Those of `candidates` that enter the pyramid from the point to `cell`, into `entering`.
  const auto enter = [&](const Corners& cell, const std::vector<std::uint32_t>& candidates,
                         std::vector<std::uint32_t>& entering) {
    entering.clear();
    const std::array<Eigen::Vector3d, 4> pyramid = {point, cell[0], cell[1], cell[2]};
    Eigen::AlignedBox3d box(point);
    for (const Eigen::Vector3d& c : cell) box.extend(c);
    for (std::uint32_t other : candidates) {
      if (box.intersects(boxes[other]) && overlaps(pyramid, corners[other])) entering.push_back(other);
    }
  };
  // Fills node `index` for `cell`, which the `entering` triangles enter, `level` cuts down.
  const auto fill = [&](auto&& self, std::uint32_t index, const Corners& cell, const std::vector<std::uint32_t>& entering,
                        int level) -> void {
    if (entering.empty()) {
      nodes_[index].state = kSeen;
      return;
    }
    if (level >= depth) {
      nodes_[index].state = kUnknown;
      return;
    }
    const auto first = static_cast<std::uint32_t>(nodes_.size());
    nodes_[index].state = kSplit;
    nodes_[index].first_child = first;
    nodes_.resize(nodes_.size() + 4);
    const std::array<Corners, 4> cells = quarters(cell);
    std::vector<std::uint32_t> inner;
    for (std::uint32_t q = 0; q < 4; ++q) {
      enter(cells[q], entering, inner);
      self(self, first + q, cells[q], inner, level + 1);
    }
  };
  std::vector<std::uint32_t> everyone(count), entering;
  for (std::size_t t = 0; t < count; ++t) everyone[t] = static_cast<std::uint32_t>(t);
  for (std::size_t t = 0; t < count; ++t) {
    const Eigen::Vector3d e1 = corners[t][1] - corners[t][0], e2 = corners[t][2] - corners[t][0];
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
    const double det = d11 * d22 - d12 * d12;
    frames_[t].origin = corners[t][0];
    frames_[t].along_u = det > 0.0 ? Eigen::Vector3d((d22 * e1 - d12 * e2) / det) : Eigen::Vector3d::Zero();
    frames_[t].along_v = det > 0.0 ? Eigen::Vector3d((d11 * e2 - d12 * e1) / det) : Eigen::Vector3d::Zero();
    roots_[t] = static_cast<std::uint32_t>(nodes_.size());
    nodes_.emplace_back();
    const Eigen::Vector3d normal = mesh.normal(t);
    if (!(std::abs(normal.dot(point - corners[t][0])) >= 1e-6)) continue;  // in its plane: unknown
    enter(corners[t], everyone, entering);
    entering.erase(std::remove(entering.begin(), entering.end(), static_cast<std::uint32_t>(t)), entering.end());
    fill(fill, roots_[t], corners[t], entering, 0);
  }
}

bool TriangleVisibility::sees(std::size_t triangle, const Eigen::Vector3d& on_triangle) const {
  if (roots_.empty()) return false;
  const Node* node = &nodes_[roots_[triangle]];
  if (node->state != kSplit) return node->state == kSeen;
  const Frame& f = frames_[triangle];
  const Eigen::Vector3d w = on_triangle - f.origin;
  double u = f.along_u.dot(w), v = f.along_v.dot(w);
  while (node->state == kSplit) {
    // The cell holding (u, v), and the point's coordinates in it (quarters' corner order).
    std::uint32_t q;
    if (u >= 0.5) {
      q = 1, u = 2.0 * u - 1.0, v = 2.0 * v;
    } else if (v >= 0.5) {
      q = 2, u = 2.0 * u, v = 2.0 * v - 1.0;
    } else if (u + v < 0.5) {
      q = 0, u = 2.0 * u, v = 2.0 * v;
    } else {
      q = 3, u = 1.0 - 2.0 * u, v = 1.0 - 2.0 * v;
    }
    node = &nodes_[node->first_child + q];
  }
  return node->state == kSeen;
}

double TriangleVisibility::shareBelow(std::uint32_t index) const {
  const Node& node = nodes_[index];
  if (node.state != kSplit) return node.state == kSeen ? 1.0 : 0.0;
  double share = 0.0;
  for (std::uint32_t q = 0; q < 4; ++q) share += 0.25 * shareBelow(node.first_child + q);
  return share;
}

double TriangleVisibility::seenShare(std::size_t triangle) const {
  return roots_.empty() ? 0.0 : shareBelow(roots_[triangle]);
}

}  // namespace room_reverb::core
