#include "room_reverb/acoustics/diffraction_scattering.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <tuple>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {
namespace {

constexpr double kVertexTolerance_m = 1e-3;

// Union-find over triangles.
std::size_t root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

using VertexKey = std::tuple<long long, long long, long long, std::size_t>;

VertexKey keyOf(const Eigen::Vector3d& p, std::size_t plane) {
  return {std::llround(p.x() / kVertexTolerance_m), std::llround(p.y() / kVertexTolerance_m),
          std::llround(p.z() / kVertexTolerance_m), plane};
}

// The patch of triangles `members`: principal axes of the area's second moment in the
// plane, the extents of the vertices along them, scaled to the area.
SurfaceExtent patchOf(const TriangleMesh& mesh, const std::vector<std::size_t>& members) {
  SurfaceExtent patch;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t t : members) {
    const double area = mesh.area(t);
    patch.area_m2 += area;
    for (int k = 0; k < 3; ++k) centroid += area / 3.0 * mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][k])];
  }
  if (!(patch.area_m2 > 0.0)) return patch;
  centroid /= patch.area_m2;
  // Second moment of each triangle about the centroid, exactly: (A / 12) (sum of the
  // vertices' outer products + the outer product of their sum), shifted.
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  for (std::size_t t : members) {
    const double area = mesh.area(t);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d q = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][k])] - centroid;
      sum += q;
      outer += q * q.transpose();
    }
    moment += area / 12.0 * (outer + sum * sum.transpose());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moment);
  // Eigenvalues ascending: the smallest is the normal's (zero for a flat patch).
  patch.axis_u = solver.eigenvectors().col(2).normalized();
  patch.axis_v = solver.eigenvectors().col(1).normalized();
  double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo, v_lo = u_lo, v_hi = -u_lo;
  for (std::size_t t : members) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d q = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][k])] - centroid;
      u_lo = std::min(u_lo, q.dot(patch.axis_u));
      u_hi = std::max(u_hi, q.dot(patch.axis_u));
      v_lo = std::min(v_lo, q.dot(patch.axis_v));
      v_hi = std::max(v_hi, q.dot(patch.axis_v));
    }
  }
  // A rectangle keeps its sides; an L-shaped or triangular piece becomes the rectangle of
  // its area with the extents' proportions.
  const double fill = std::sqrt(std::min(1.0, patch.area_m2 / ((u_hi - u_lo) * (v_hi - v_lo))));
  patch.width_u_m = (u_hi - u_lo) * fill;
  patch.width_v_m = (v_hi - v_lo) * fill;
  return patch;
}

// min(1, f / f_g) for one axis, f_g = c a* / (2 w^2).
double axisShare(double width_m, double characteristic_distance_m, double frequency_hz, double speed_of_sound_m_s) {
  if (!(characteristic_distance_m > 0.0)) return 1.0;
  const double limit_hz = speed_of_sound_m_s * characteristic_distance_m / (2.0 * width_m * width_m);
  return std::min(1.0, frequency_hz / limit_hz);
}

}  // namespace

std::vector<SurfaceExtent> surfaceExtents(const TriangleMesh& mesh, const std::vector<std::size_t>& triangle_plane,
                                         std::vector<std::size_t>& triangle_patch) {
  const std::size_t n = mesh.triangleCount();
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  std::map<VertexKey, std::size_t> first_with_vertex;
  for (std::size_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      const VertexKey key = keyOf(mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][k])], triangle_plane[t]);
      const auto [it, inserted] = first_with_vertex.emplace(key, t);
      if (!inserted) parent[root(parent, t)] = root(parent, it->second);
    }
  }
  std::map<std::size_t, std::vector<std::size_t>> groups;
  for (std::size_t t = 0; t < n; ++t) groups[root(parent, t)].push_back(t);
  std::vector<SurfaceExtent> patches;
  triangle_patch.assign(n, 0);
  for (const auto& [group_root, members] : groups) {
    for (std::size_t t : members) triangle_patch[t] = patches.size();
    patches.push_back(patchOf(mesh, members));
  }
  return patches;
}

double characteristicDistance(double incoming_m, double outgoing_m) {
  const double sum = incoming_m + outgoing_m;
  return sum > 0.0 ? 2.0 * incoming_m * outgoing_m / sum : 0.0;
}

double specularShare(const SurfaceExtent& patch, const Eigen::Vector3d& incident, double characteristic_distance_m,
                     double frequency_hz, double speed_of_sound_m_s) {
  const double du = incident.dot(patch.axis_u), dv = incident.dot(patch.axis_v);
  const double seen_u = patch.width_u_m * std::sqrt(std::max(0.0, 1.0 - du * du));
  const double seen_v = patch.width_v_m * std::sqrt(std::max(0.0, 1.0 - dv * dv));
  if (!(seen_u > 0.0) || !(seen_v > 0.0)) return std::numeric_limits<double>::min();
  return std::max(std::numeric_limits<double>::min(),
                  axisShare(seen_u, characteristic_distance_m, frequency_hz, speed_of_sound_m_s) *
                      axisShare(seen_v, characteristic_distance_m, frequency_hz, speed_of_sound_m_s));
}

OctaveBandValues withDiffractionScattering(const OctaveBandValues& material_scattering, const SurfaceExtent& patch,
                                           const Eigen::Vector3d& incident, double characteristic_distance_m,
                                           double speed_of_sound_m_s, const OctaveBandValues& band_centres_hz) {
  OctaveBandValues combined{};
  for (int b = 0; b < kOctaveBandCount; ++b) {
    const double share = specularShare(patch, incident, characteristic_distance_m, band_centres_hz[b], speed_of_sound_m_s);
    combined[b] = 1.0 - (1.0 - material_scattering[b]) * share;
  }
  return combined;
}

}  // namespace room_reverb::core
