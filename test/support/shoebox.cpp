#include "shoebox.h"

namespace room_reverb::test {

core::TriangleMesh shoeboxMesh(const Eigen::Vector3d& size, const std::string& material) {
  core::TriangleMesh mesh;
  mesh.material_names.push_back(material);
  const double x = size.x(), y = size.y(), z = size.z();
  mesh.vertices = {{0, 0, 0}, {x, 0, 0}, {x, y, 0}, {0, y, 0}, {0, 0, z}, {x, 0, z}, {x, y, z}, {0, y, z}};
  // Each face as two triangles, wound so the normal points into the room.
  const int quads[6][4] = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1}, {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 5, 6, 2}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
    mesh.triangle_material.push_back(0);
    mesh.triangle_material.push_back(0);
  }
  return mesh;
}

core::MaterialLibrary uniformLibrary(double absorption, double scattering, const std::string& name) {
  core::MaterialLibrary library;
  core::AcousticMaterial material;
  material.name = name;
  material.absorption.fill(absorption);
  material.scattering.fill(scattering);
  material.source = "test";
  library.add(material);
  return library;
}

}  // namespace room_reverb::test
