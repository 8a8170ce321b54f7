#pragma once
// A triangle mesh with a material per triangle: the geometry every simulation runs on.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

namespace room_reverb::core {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;       // metres, room frame (x forward, y left, z up)
  std::vector<std::array<int, 3>> triangles;   // vertex indices
  std::vector<int> triangle_material;          // per triangle, index into material_names
  std::vector<std::string> material_names;     // as named by the source (file or room model)

  std::size_t triangleCount() const { return triangles.size(); }
  // Unit normal by the right-hand rule over (v0, v1, v2).
  Eigen::Vector3d normal(std::size_t triangle) const;
  double area(std::size_t triangle) const;
  double totalArea() const;
  // Appends another mesh; materials are merged by name.
  void append(const TriangleMesh& other);
  // Index of a material name, added if new.
  int materialIndex(const std::string& name);
};

// Throws InputError naming `what` for an empty mesh, non-finite vertices, vertex indices
// out of range, or a material index out of range. Degenerate (zero-area) triangles are
// removed, not an error.
void validateMesh(TriangleMesh& mesh, const std::string& what);

// Files written with y up (as the BRAS AC3D model) are turned into the room frame by a
// +90 degree rotation about x: (x, y, z) -> (x, -z, y).
enum class UpAxis { kZ, kY };
Eigen::Vector3d yUpToZUp(const Eigen::Vector3d& p);

// Reads AC3D (.ac), Wavefront OBJ (.obj, materials from usemtl) or PLY (.ply, ASCII or
// binary little-endian; material names from a face property material_index and
// "comment material <index> <name>" header lines, else "default"). Convex polygons
// are triangulated as fans, concave ones by ear clipping inside their outline.
// Throws InputError with the file and line for anything it cannot
// parse, and for a mesh validateMesh rejects.
TriangleMesh loadMesh(const std::string& path, UpAxis up = UpAxis::kZ);

}  // namespace room_reverb::core
