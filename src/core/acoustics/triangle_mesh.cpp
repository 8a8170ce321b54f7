#include "room_reverb/acoustics/triangle_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

Eigen::Vector3d crossOf(const TriangleMesh& mesh, std::size_t triangle) {
  const auto& t = mesh.triangles[triangle];
  const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(t[0])];
  const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(t[1])];
  const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(t[2])];
  return (b - a).cross(c - a);
}

// A triangle counts as degenerate when its vertices are collinear to within rounding: its
// height over the longest edge is below 1e-12 of that edge. A fixed area threshold would
// not do, because a mesh in millimetres and one in kilometres must be judged alike.
bool isDegenerate(const TriangleMesh& mesh, std::size_t triangle) {
  const auto& t = mesh.triangles[triangle];
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(t[0])];
  const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(t[1])];
  const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(t[2])];
  const double longest_sq = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  if (longest_sq == 0.0) return true;
  // |cross| = 2 * area = longest edge * height.
  return (b - a).cross(c - a).norm() <= 1e-12 * longest_sq;
}

}  // namespace

Eigen::Vector3d TriangleMesh::normal(std::size_t triangle) const {
  const Eigen::Vector3d c = crossOf(*this, triangle);
  const double n = c.norm();
  // A degenerate triangle has no direction; zero is safer than NaN for callers that sum.
  return n > 0.0 ? Eigen::Vector3d(c / n) : Eigen::Vector3d::Zero();
}

double TriangleMesh::area(std::size_t triangle) const { return 0.5 * crossOf(*this, triangle).norm(); }

double TriangleMesh::totalArea() const {
  double sum = 0.0;
  for (std::size_t i = 0; i < triangles.size(); ++i) sum += area(i);
  return sum;
}

int TriangleMesh::materialIndex(const std::string& name) {
  const auto it = std::find(material_names.begin(), material_names.end(), name);
  if (it != material_names.end()) return static_cast<int>(it - material_names.begin());
  material_names.push_back(name);
  return static_cast<int>(material_names.size()) - 1;
}

void TriangleMesh::append(const TriangleMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  // The other mesh's material indices refer to its own name list; map them onto ours.
  std::vector<int> remap(other.material_names.size());
  for (std::size_t m = 0; m < other.material_names.size(); ++m) {
    remap[m] = materialIndex(other.material_names[m]);
  }
  for (std::size_t i = 0; i < other.triangles.size(); ++i) {
    const auto& t = other.triangles[i];
    triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    const int m = i < other.triangle_material.size() ? other.triangle_material[i] : -1;
    triangle_material.push_back(m >= 0 && static_cast<std::size_t>(m) < remap.size()
                                    ? remap[static_cast<std::size_t>(m)]
                                    : m);  // left out of range on purpose: validateMesh reports it
  }
}

void validateMesh(TriangleMesh& mesh, const std::string& what) {
  if (mesh.vertices.empty() || mesh.triangles.empty()) {
    throw InputError(what + ": the mesh is empty (" + std::to_string(mesh.vertices.size()) +
                     " vertices, " + std::to_string(mesh.triangles.size()) + " triangles)");
  }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!mesh.vertices[v].allFinite()) {
      std::ostringstream os;
      os << what << ": vertex " << v << " is not finite (" << mesh.vertices[v].transpose() << ")";
      throw InputError(os.str());
    }
  }
  if (mesh.triangle_material.size() != mesh.triangles.size()) {
    throw InputError(what + ": " + std::to_string(mesh.triangles.size()) + " triangles but " +
                     std::to_string(mesh.triangle_material.size()) + " triangle materials");
  }
  const auto vertex_count = static_cast<long long>(mesh.vertices.size());
  const auto material_count = static_cast<long long>(mesh.material_names.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (const int index : mesh.triangles[i]) {
      if (index < 0 || index >= vertex_count) {
        throw InputError(what + ": triangle " + std::to_string(i) + " refers to vertex " +
                         std::to_string(index) + ", but there are " + std::to_string(vertex_count) +
                         " vertices (0.." + std::to_string(vertex_count - 1) + ")");
      }
    }
    const int m = mesh.triangle_material[i];
    if (m < 0 || m >= material_count) {
      throw InputError(what + ": triangle " + std::to_string(i) + " has material index " +
                       std::to_string(m) + ", but there are " + std::to_string(material_count) +
                       " material names");
    }
  }

  // Zero-area triangles carry no sound energy and would give NaN normals to a ray tracer;
  // they are common in exported models (collinear fan corners), so they go quietly.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (isDegenerate(mesh, i)) continue;
    mesh.triangles[kept] = mesh.triangles[i];
    mesh.triangle_material[kept] = mesh.triangle_material[i];
    ++kept;
  }
  if (kept == 0) {
    throw InputError(what + ": all " + std::to_string(mesh.triangles.size()) +
                     " triangles have zero area");
  }
  mesh.triangles.resize(kept);
  mesh.triangle_material.resize(kept);
}

Eigen::Vector3d yUpToZUp(const Eigen::Vector3d& p) { return {p.x(), -p.z(), p.y()}; }

}  // namespace room_reverb::core
