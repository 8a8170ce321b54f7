#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <unistd.h>

#include "test_files.h"
#include "room_reverb/acoustics/triangle_mesh.h"
#include "room_reverb/common/error.h"

using namespace room_reverb::core;
namespace fs = std::filesystem;

namespace {

using room_reverb::test::expectInputError;
using room_reverb::test::tempPath;
using room_reverb::test::writeFile;

// Signed enclosed volume by the divergence theorem: positive when normals point outward.
double signedVolume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const auto& t : mesh.triangles) {
    volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6.0;
  }
  return volume;
}

Eigen::Vector3d centroid(const TriangleMesh& mesh, std::size_t t) {
  const auto& tri = mesh.triangles[t];
  return (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
}

// Every triangle of a closed box faces away from the box centre, along an axis.
void expectOutwardAxisNormals(const TriangleMesh& mesh, const Eigen::Vector3d& box_centre) {
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Eigen::Vector3d n = mesh.normal(t);
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-12) << "triangle " << t;
    EXPECT_GT(n.dot(centroid(mesh, t) - box_centre), 0.0) << "triangle " << t;
  }
}

std::map<std::string, double> areaByMaterial(const TriangleMesh& mesh) {
  std::map<std::string, double> areas;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    areas[mesh.material_names[mesh.triangle_material[t]]] += mesh.area(t);
  }
  return areas;
}

// A 2 m cube centred at (0, 0, 1): six quads wound counter-clockwise seen from outside, the
// bottom one "floor_mat", the rest "wall_mat". OBJ indices start at 1.
const char* kCubeObj = R"(# cube
mtllib cube.mtl
v -1 -1 0
v 1 -1 0
v -1 1 0
v 1 1 0
v -1 -1 2
v 1 -1 2
v -1 1 2
v 1 1 2
vt 0 0
vn 0 0 1
o cube
usemtl floor_mat
f 1 3 4 2
usemtl wall_mat
f 5/1 6/1 8/1 7/1
f 1//1 5//1 7//1 3//1
f 2/1/1 4/1/1 8/1/1 6/1/1
f -8 -7 -3 -4
l 1 2
f 3 7 8 4
)";

}  // namespace

TEST(TriangleMesh, AreaNormalAndMaterialMerge) {
  TriangleMesh a;
  a.vertices = {{0, 0, 0}, {3, 0, 0}, {0, 4, 0}};
  a.triangles = {{0, 1, 2}};
  a.triangle_material = {a.materialIndex("concrete")};
  EXPECT_DOUBLE_EQ(a.area(0), 6.0);
  EXPECT_TRUE(a.normal(0).isApprox(Eigen::Vector3d::UnitZ()));

  TriangleMesh b;
  b.vertices = {{0, 0, 1}, {0, 2, 1}, {2, 0, 1}};
  b.triangles = {{0, 1, 2}};
  b.triangle_material = {b.materialIndex("glass")};
  b.materialIndex("concrete");
  b.triangles.push_back({0, 2, 1});
  b.triangle_material.push_back(1);

  a.append(b);
  ASSERT_EQ(a.triangleCount(), 3u);
  ASSERT_EQ(a.vertices.size(), 6u);
  EXPECT_EQ(a.material_names, (std::vector<std::string>{"concrete", "glass"}));
  EXPECT_EQ(a.triangle_material, (std::vector<int>{0, 1, 0}));
  EXPECT_EQ(a.triangles[1], (std::array<int, 3>{3, 4, 5}));
  EXPECT_TRUE(a.normal(1).isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_DOUBLE_EQ(a.totalArea(), 6.0 + 2.0 + 2.0);
  EXPECT_EQ(a.materialIndex("glass"), 1);
}

TEST(TriangleMesh, YUpToZUpIsAQuarterTurnAboutX) {
  EXPECT_TRUE(yUpToZUp({1, 2, 3}).isApprox(Eigen::Vector3d(1, -3, 2)));
  // y up becomes z up; a rotation keeps handedness (and so the winding of triangles).
  EXPECT_TRUE(yUpToZUp(Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d x = yUpToZUp(Eigen::Vector3d::UnitX());
  const Eigen::Vector3d y = yUpToZUp(Eigen::Vector3d::UnitY());
  EXPECT_TRUE(x.cross(y).isApprox(yUpToZUp(Eigen::Vector3d::UnitZ())));
}

TEST(TriangleMesh, ValidateDropsDegenerateTrianglesAndRejectsBadMeshes) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 1, 2}};  // the last two have no area
  mesh.triangle_material = {0, 0, 0};
  mesh.material_names = {"m"};
  validateMesh(mesh, "test mesh");
  ASSERT_EQ(mesh.triangleCount(), 1u);
  EXPECT_EQ(mesh.triangle_material.size(), 1u);

  TriangleMesh empty;
  expectInputError([&] { validateMesh(empty, "test mesh"); }, {"test mesh", "empty"});

  TriangleMesh nan_vertex = mesh;
  nan_vertex.vertices[2].y() = std::numeric_limits<double>::quiet_NaN();
  expectInputError([&] { validateMesh(nan_vertex, "test mesh"); }, {"test mesh", "vertex 2", "not finite"});

  TriangleMesh bad_index = mesh;
  bad_index.triangles[0][2] = 7;
  expectInputError([&] { validateMesh(bad_index, "test mesh"); }, {"test mesh", "vertex 7"});

  TriangleMesh bad_material = mesh;
  bad_material.triangle_material[0] = 1;
  expectInputError([&] { validateMesh(bad_material, "test mesh"); }, {"material index 1"});

  TriangleMesh all_degenerate = mesh;
  all_degenerate.triangles = {{0, 1, 3}};
  expectInputError([&] { validateMesh(all_degenerate, "test mesh"); }, {"zero area"});
}

TEST(MeshIo, ObjCube) {
  const TriangleMesh mesh = loadMesh(writeFile("cube.obj", kCubeObj));
  EXPECT_EQ(mesh.vertices.size(), 8u);
  ASSERT_EQ(mesh.triangleCount(), 12u);
  EXPECT_NEAR(mesh.totalArea(), 24.0, 1e-12);
  EXPECT_NEAR(signedVolume(mesh), 8.0, 1e-12);
  expectOutwardAxisNormals(mesh, {0, 0, 1});
  EXPECT_EQ(mesh.material_names, (std::vector<std::string>{"floor_mat", "wall_mat"}));
  const auto areas = areaByMaterial(mesh);
  EXPECT_NEAR(areas.at("floor_mat"), 4.0, 1e-12);
  EXPECT_NEAR(areas.at("wall_mat"), 20.0, 1e-12);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.triangle_material[t] == 0) {
      EXPECT_TRUE(mesh.normal(t).isApprox(-Eigen::Vector3d::UnitZ()));
    }
  }
}

TEST(MeshIo, ObjWithoutUsemtlIsDefaultAndYUpIsTurned) {
  // One triangle in the y = 0 plane of a y-up file, facing +y (up): on the floor once turned.
  const std::string path = writeFile("yup.obj", "v 0 0 0\nv 1 0 0\nv 0 0 -1\nf 1 2 3\n");
  const TriangleMesh as_is = loadMesh(path);
  EXPECT_EQ(as_is.material_names, (std::vector<std::string>{"default"}));
  EXPECT_TRUE(as_is.normal(0).isApprox(Eigen::Vector3d::UnitY()));
  const TriangleMesh turned = loadMesh(path, UpAxis::kY);
  EXPECT_TRUE(turned.normal(0).isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(turned.vertices[2].isApprox(Eigen::Vector3d(0, 1, 0)));
}

TEST(MeshIo, ConcavePolygonIsTriangulatedInsideItsOutline) {
  // An L-shaped floor (3 m^2): a fan from the first corner would cover the notch too.
  const std::string path = writeFile("l_shape.obj",
                                     "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
                                     "f 3 4 5 6 1 2\n");
  const TriangleMesh mesh = loadMesh(path);
  ASSERT_EQ(mesh.triangleCount(), 4u);
  EXPECT_NEAR(mesh.totalArea(), 3.0, 1e-12);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    EXPECT_TRUE(mesh.normal(t).isApprox(Eigen::Vector3d::UnitZ())) << "winding kept, triangle " << t;
    const Eigen::Vector3d c = centroid(mesh, t);
    EXPECT_FALSE(c.x() > 1.0 && c.y() > 1.0) << "triangle " << t << " lies in the notch";
  }
  // Wound the other way round, it faces down and covers the same outline.
  const TriangleMesh reversed = loadMesh(writeFile("l_shape_reversed.obj",
                                                   "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
                                                   "f 5 4 3 2 1 6\n"));
  ASSERT_EQ(reversed.triangleCount(), 4u);
  EXPECT_NEAR(reversed.totalArea(), 3.0, 1e-12);
  for (std::size_t t = 0; t < reversed.triangleCount(); ++t) {
    EXPECT_TRUE(reversed.normal(t).isApprox(-Eigen::Vector3d::UnitZ())) << "triangle " << t;
  }
}

TEST(MeshIo, PlyAsciiCubeWithMaterials) {
  const std::string path = writeFile("cube_ascii.ply", R"(ply
format ascii 1.0
comment material 0 floor_mat
comment material 1 wall mat with spaces
element vertex 8
property float x
property float y
property float z
property uchar red
element face 6
property list uchar int vertex_indices
property int material_index
end_header
-1 -1 0 255
1 -1 0 255
-1 1 0 255
1 1 0 255
-1 -1 2 255
1 -1 2 255
-1 1 2 255
1 1 2 255
4 0 2 3 1 0
4 4 5 7 6 1
4 0 4 6 2 1
4 1 3 7 5 1
4 0 1 5 4 1
4 2 6 7 3 2
)");
  const TriangleMesh mesh = loadMesh(path);
  ASSERT_EQ(mesh.triangleCount(), 12u);
  EXPECT_NEAR(mesh.totalArea(), 24.0, 1e-12);
  EXPECT_NEAR(signedVolume(mesh), 8.0, 1e-12);
  expectOutwardAxisNormals(mesh, {0, 0, 1});
  const auto areas = areaByMaterial(mesh);
  EXPECT_NEAR(areas.at("floor_mat"), 4.0, 1e-12);
  EXPECT_NEAR(areas.at("wall mat with spaces"), 16.0, 1e-12);
  EXPECT_NEAR(areas.at("material_2"), 4.0, 1e-12);  // no comment names index 2
}

namespace {

template <typename T>
void putLittleEndian(std::string& out, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  std::uint64_t bits = 0;
  for (std::size_t b = 0; b < sizeof(T); ++b) bits |= static_cast<std::uint64_t>(bytes[b]) << (8 * b);
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  if (first == 0) {  // big-endian host: reverse the bytes
    bits = 0;
    for (std::size_t b = 0; b < sizeof(T); ++b) bits |= static_cast<std::uint64_t>(bytes[sizeof(T) - 1 - b]) << (8 * b);
  }
  for (std::size_t b = 0; b < sizeof(T); ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xFF));
}

std::string binaryCubePly(bool truncate) {
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment material 3 floor_mat\n"
      "element vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 6\nproperty uchar material_index\nproperty list uchar uint vertex_indices\n"
      "end_header\n";
  const double corners[8][3] = {{-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}, {1, 1, 0},
                                {-1, -1, 2}, {1, -1, 2}, {-1, 1, 2}, {1, 1, 2}};
  for (const auto& c : corners) {
    for (double v : c) putLittleEndian(out, v);
  }
  const std::uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}};
  for (int f = 0; f < 6; ++f) {
    putLittleEndian(out, static_cast<std::uint8_t>(f == 0 ? 3 : 4));
    putLittleEndian(out, static_cast<std::uint8_t>(4));
    for (std::uint32_t index : faces[f]) putLittleEndian(out, index);
  }
  if (truncate) out.resize(out.size() - 5);
  return out;
}

}  // namespace

TEST(MeshIo, PlyBinaryLittleEndianCube) {
  const TriangleMesh mesh = loadMesh(writeFile("cube_binary.ply", binaryCubePly(false)));
  ASSERT_EQ(mesh.triangleCount(), 12u);
  EXPECT_NEAR(mesh.totalArea(), 24.0, 1e-12);
  EXPECT_NEAR(signedVolume(mesh), 8.0, 1e-12);
  expectOutwardAxisNormals(mesh, {0, 0, 1});
  const auto areas = areaByMaterial(mesh);
  EXPECT_NEAR(areas.at("floor_mat"), 4.0, 1e-12);
  EXPECT_NEAR(areas.at("material_4"), 20.0, 1e-12);

  expectInputError([&] { loadMesh(writeFile("cube_truncated.ply", binaryCubePly(true))); },
                         {"cube_truncated.ply", "face 5", "ends"});
}

TEST(MeshIo, Ac3dHierarchyWithLocRotAndLineSurfaces) {
  // A 2 x 1 x 1 box; rot turns it a quarter about z (x -> y), its loc and its parent's loc
  // move it to x in [9, 10], y in [5, 7], z in [0, 1]. Two line surfaces (closed and open)
  // must be skipped.
  const std::string path = writeFile("box.ac", R"(AC3Db
MATERIAL "wood" rgb 1 1 1  amb 0.2 0.2 0.2  emis 0 0 0  spec 0.5 0.5 0.5  shi 10  trans 0
MATERIAL "floor tiles" rgb 1 1 1  amb 0.2 0.2 0.2  emis 0 0 0  spec 0.5 0.5 0.5  shi 10  trans 0
OBJECT world
loc 10 0 0
kids 1
OBJECT poly
name "box"
crease 30.0
subdiv 0
data 9
some data
rot 0 -1 0 1 0 0 0 0 1
loc 0 5 0
numvert 8
0 0 0
2 0 0
0 1 0
2 1 0
0 0 1
2 0 1
0 1 1
2 1 1
numsurf 8
SURF 0x10
mat 1
refs 4
0 0 0
2 0 1
3 1 1
1 1 0
SURF 0x10
mat 0
refs 4
4 0 0
5 0 0
7 0 0
6 0 0
SURF 0x10
mat 0
refs 4
0 0 0
4 0 0
6 0 0
2 0 0
SURF 0x2
mat 0
refs 2
0 0 0
7 0 0
SURF 0x10
mat 0
refs 4
1 0 0
3 0 0
7 0 0
5 0 0
SURF 0x10
mat 0
refs 4
0 0 0
1 0 0
5 0 0
4 0 0
SURF 0x31
mat 0
refs 3
0 0 0
5 0 0
6 0 0
SURF 0x10
mat 0
refs 4
2 0 0
6 0 0
7 0 0
3 0 0
kids 0
)");
  const TriangleMesh mesh = loadMesh(path);
  ASSERT_EQ(mesh.triangleCount(), 12u);
  EXPECT_NEAR(mesh.totalArea(), 10.0, 1e-12);
  EXPECT_NEAR(signedVolume(mesh), 2.0, 1e-12);
  Eigen::Vector3d lo = mesh.vertices[0], hi = mesh.vertices[0];
  for (const auto& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3d(9, 5, 0))) << lo.transpose();
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3d(10, 7, 1))) << hi.transpose();
  expectOutwardAxisNormals(mesh, {9.5, 6, 0.5});
  EXPECT_EQ(mesh.material_names, (std::vector<std::string>{"wood", "floor tiles"}));
  EXPECT_NEAR(areaByMaterial(mesh).at("floor tiles"), 2.0, 1e-12);
}

TEST(MeshIo, Ac3dWithoutMaterialLinesIsDefault) {
  const TriangleMesh mesh = loadMesh(writeFile("plain.ac", "AC3Db\nOBJECT poly\nnumvert 3\n0 0 0\n1 0 0\n0 1 0\n"
                                                           "numsurf 1\nSURF 0x0\nrefs 3\n0 0 0\n1 0 0\n2 0 0\nkids 0\n"));
  ASSERT_EQ(mesh.triangleCount(), 1u);
  EXPECT_EQ(mesh.material_names, (std::vector<std::string>{"default"}));
  EXPECT_NEAR(mesh.totalArea(), 0.5, 1e-15);
}

TEST(MeshIo, ErrorsNameTheFileAndLine) {
  expectInputError([] { loadMesh(tempPath("missing.obj").string()); }, {"missing.obj", "no such file"});
  expectInputError([] { loadMesh(writeFile("mesh.stl", "solid x\n")); }, {"mesh.stl", "unknown mesh format"});

  // OBJ: a coordinate that is no number, NaN, an index past the end, index 0, no faces.
  expectInputError([] { loadMesh(writeFile("word.obj", "v 0 0 0\nv 1 zero 0\n")); },
                         {"word.obj:2:", "'zero' is not a number"});
  expectInputError([] { loadMesh(writeFile("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")); },
                         {"nan.obj:3:", "not finite"});
  expectInputError([] { loadMesh(writeFile("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")); },
                         {"index.obj:4:", "out of range"});
  expectInputError([] { loadMesh(writeFile("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n")); },
                         {"zero.obj:4:", "out of range"});
  expectInputError([] { loadMesh(writeFile("empty.obj", "# nothing\nv 0 0 0\n")); }, {"empty.obj", "empty"});
  expectInputError([] { loadMesh(writeFile("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n")); },
                         {"two.obj:3:", "at least three"});

  // AC3D: a reference past the object's vertices, a count the file does not hold, a bad
  // material index, not AC3D at all.
  const std::string ac_head = "AC3Db\nMATERIAL \"m\" rgb 1 1 1\nOBJECT poly\nnumvert 3\n0 0 0\n1 0 0\n0 1 0\n";
  expectInputError([&] { loadMesh(writeFile("ref.ac", ac_head + "numsurf 1\nSURF 0x10\nmat 0\nrefs 3\n0 0 0\n1 0 0\n3 0 0\nkids 0\n")); },
                         {"ref.ac:14:", "vertex index 3", "out of range"});
  expectInputError([&] { loadMesh(writeFile("short.ac", "AC3Db\nOBJECT poly\nnumvert 8\n0 0 0\n1 0 0\n")); },
                         {"short.ac", "file ends", "vertex 3 of 8"});
  expectInputError([&] { loadMesh(writeFile("count.ac", "AC3Db\nOBJECT poly\nnumvert -2\nkids 0\n")); },
                         {"count.ac:3:", "negative"});
  expectInputError([&] { loadMesh(writeFile("mat.ac", ac_head + "numsurf 1\nSURF 0x10\nmat 4\nrefs 3\n0 0 0\n1 0 0\n2 0 0\nkids 0\n")); },
                         {"mat.ac:10:", "material index 4"});
  expectInputError([&] { loadMesh(writeFile("nan.ac", "AC3Db\nOBJECT poly\nnumvert 1\n0 inf 0\nkids 0\n")); },
                         {"nan.ac:4:", "not finite"});
  expectInputError([&] { loadMesh(writeFile("type.ac", ac_head + "numsurf 1\nSURF 0x14\nmat 0\nrefs 3\n0 0 0\n1 0 0\n2 0 0\nkids 0\n")); },
                         {"type.ac:9:", "unsupported SURF type 4"});
  expectInputError([&] { loadMesh(writeFile("notac.ac", "hello\n")); }, {"notac.ac:1:", "not an AC3D file"});
  expectInputError([&] { loadMesh(writeFile("stray.ac", "AC3Db\nOBJECT poly\nnumvert 1\n0 0 0\n1 1 1\nkids 0\n")); },
                         {"stray.ac:5:", "unexpected '1'"});
  expectInputError([&] { loadMesh(writeFile("emptyac.ac", "AC3Db\nOBJECT world\nkids 0\n")); },
                         {"emptyac.ac", "empty"});

  // PLY: unsupported byte order, index out of range (with its line), missing coordinates.
  expectInputError([] { loadMesh(writeFile("big.ply", "ply\nformat binary_big_endian 1.0\nend_header\n")); },
                         {"big.ply:2:", "binary_big_endian"});
  expectInputError(
      [] {
        loadMesh(writeFile("range.ply",
                           "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n"));
      },
      {"range.ply:13", "vertex index 9"});
  expectInputError(
      [] {
        loadMesh(writeFile("noz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n"));
      },
      {"noz.ply:3:", "x, y and z"});
}

// The BRAS CR2 seminar room (scene 9): the AC3D model the BRAS database ships, y up.
TEST(MeshIo, BrasCr2SeminarRoom) {
  const std::string path = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/bras_cr2/geometry/cr2_scene9.ac";
  const TriangleMesh mesh = loadMesh(path, UpAxis::kY);
  ASSERT_EQ(mesh.material_names.size(), 5u);
  EXPECT_EQ(mesh.material_names,
            (std::vector<std::string>{"mat_scene09_concrete", "mat_scene09_windows", "mat_scene09_ceiling",
                                      "mat_scene09_plaster", "mat_scene09_floor"}));
  // BRAS (mat_CR2_description.txt): S = 202.53 m^2, V = 146.1 m^3, and the area per
  // material below.
  EXPECT_NEAR(mesh.totalArea(), 202.53, 0.05);
  const auto areas = areaByMaterial(mesh);
  EXPECT_NEAR(areas.at("mat_scene09_plaster"), 34.93, 0.02);
  EXPECT_NEAR(areas.at("mat_scene09_concrete"), 56.94, 0.02);
  EXPECT_NEAR(areas.at("mat_scene09_windows"), 9.75, 0.02);
  EXPECT_NEAR(areas.at("mat_scene09_floor"), 49.29, 0.02);
  EXPECT_NEAR(areas.at("mat_scene09_ceiling"), 51.62, 0.02);
  // The model's polygons are wound with normals pointing out of the room, so the signed
  // divergence-theorem volume is positive.
  EXPECT_NEAR(signedVolume(mesh), 146.1, 0.1);

  // After the y-up -> z-up turn the floor lies at z = 0, horizontal, facing down (out of
  // the room), and the ceiling 2.988 m above it.
  double floor_area_horizontal = 0.0;
  int horizontal = 0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Eigen::Vector3d n = mesh.normal(t);
    if (std::abs(std::abs(n.z()) - 1.0) < 1e-9) ++horizontal;
    if (mesh.material_names[mesh.triangle_material[t]] != "mat_scene09_floor") continue;
    EXPECT_NEAR(n.z(), -1.0, 1e-9) << "floor triangle " << t;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mesh.vertices[mesh.triangles[t][k]].z(), 0.0, 1e-9);
    floor_area_horizontal += mesh.area(t);
  }
  EXPECT_GT(horizontal, 100);
  EXPECT_NEAR(floor_area_horizontal, 49.29, 0.02);
  double top = -1e9, bottom = 1e9;
  for (const auto& v : mesh.vertices) {
    top = std::max(top, v.z());
    bottom = std::min(bottom, v.z());
  }
  EXPECT_NEAR(bottom, 0.0, 1e-9);
  EXPECT_NEAR(top, 2.988, 1e-9);

  // Read as if z were up, the same floor stands on its edge.
  const TriangleMesh raw = loadMesh(path);
  for (std::size_t t = 0; t < raw.triangleCount(); ++t) {
    if (raw.material_names[raw.triangle_material[t]] == "mat_scene09_floor") {
      EXPECT_NEAR(raw.normal(t).y(), -1.0, 1e-9);
    }
  }
}
