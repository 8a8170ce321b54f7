#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <unistd.h>

#include "test_files.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/common/error.h"

using namespace room_reverb::core;
namespace fs = std::filesystem;

namespace {

using room_reverb::test::expectInputError;
using room_reverb::test::tempPath;
using room_reverb::test::writeFile;

// The example of DESIGN.md ("File formats shared by the tools"), verbatim.
const char* kDesignExample = R"(frame: room                      # origin at a floor corner, x and y along the walls, z up
room_box:
  size_m: [6.64, 3.46, 2.67]     # inner extent along x, y, z
  has_ceiling: true              # false for a courtyard: the top is open sky
surfaces:                        # the box's inner faces
  floor:      {material: parquet_on_concrete, confidence: 0.9}
  ceiling:    {material: plaster_smooth, confidence: 0.8}
  wall_x_min: {material: plaster_smooth, confidence: 0.8}
  wall_x_max: {material: glass_thick, confidence: 0.6}
  wall_y_min: {material: plaster_smooth, confidence: 0.8}
  wall_y_max: {material: brick_bare, confidence: 0.7}
objects:                         # labelled cuboids inside the room
  - {label: table, material: wood_panel, center_m: [2.0, 1.5, 0.37], size_m: [1.6, 0.8, 0.74], yaw_rad: 0.0, confidence: 0.7}
materials:                       # optional: materials defined inline, by octave band 63 Hz..16 kHz
  my_panel: {absorption: [0.3, 0.3, 0.35, 0.5, 0.6, 0.6, 0.6, 0.6, 0.6], scattering: [0.1, 0.1, 0.1, 0.2, 0.3, 0.4, 0.5, 0.5, 0.5]}
rig_in_room: {position_m: [1.59, 4.10, 1.71], rotation_xyzw: [0, 0, 0, 1]}
air: {enabled: true, temperature_c: 20.0, humidity_percent: 50.0}   # optional; these are the defaults
)";

// Every face a different material, so faces can be told apart in the mesh.
const char* kMinimal = R"(room_box: {size_m: [4, 3, 2.5]}
surfaces:
  floor: {material: f}
  ceiling: {material: c}
  wall_x_min: {material: x0}
  wall_x_max: {material: x1}
  wall_y_min: {material: y0}
  wall_y_max: {material: y1}
)";

// kMinimal with one line replaced (the replacement must occur exactly once).
std::string minimalWith(const std::string& from, const std::string& to) {
  std::string text = kMinimal;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

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

AcousticMaterial flatMaterial(const std::string& name, double absorption) {
  AcousticMaterial m;
  m.name = name;
  m.absorption.fill(absorption);
  m.scattering.fill(0.1);
  return m;
}

}  // namespace

TEST(RoomModel, ParsesTheDesignExample) {
  const RoomModel model = parseRoomModel(kDesignExample);
  EXPECT_EQ(model.frame, "room");
  EXPECT_EQ(model.size_m, Eigen::Vector3d(6.64, 3.46, 2.67));
  EXPECT_TRUE(model.has_ceiling);
  ASSERT_EQ(model.surfaces.size(), 6u);
  EXPECT_EQ(model.surfaces.at("floor").material, "parquet_on_concrete");
  EXPECT_DOUBLE_EQ(model.surfaces.at("floor").confidence, 0.9);
  EXPECT_EQ(model.surfaces.at("wall_x_max").material, "glass_thick");
  EXPECT_DOUBLE_EQ(model.surfaces.at("wall_x_max").confidence, 0.6);
  EXPECT_EQ(model.surfaces.at("wall_y_max").material, "brick_bare");
  ASSERT_EQ(model.objects.size(), 1u);
  const CuboidObject& table = model.objects[0];
  EXPECT_EQ(table.label, "table");
  EXPECT_EQ(table.material, "wood_panel");
  EXPECT_EQ(table.center_m, Eigen::Vector3d(2.0, 1.5, 0.37));
  EXPECT_EQ(table.size_m, Eigen::Vector3d(1.6, 0.8, 0.74));
  EXPECT_EQ(table.yaw_rad, 0.0);
  EXPECT_DOUBLE_EQ(table.confidence, 0.7);
  ASSERT_EQ(model.inline_materials.size(), 1u);
  EXPECT_EQ(model.inline_materials[0].name, "my_panel");
  EXPECT_DOUBLE_EQ(model.inline_materials[0].absorption[2], 0.35);
  EXPECT_DOUBLE_EQ(model.inline_materials[0].scattering[8], 0.5);
  EXPECT_EQ(model.rig_position_m, Eigen::Vector3d(1.59, 4.10, 1.71));
  EXPECT_TRUE(model.rig_rotation.isApprox(Eigen::Quaterniond::Identity()));
  EXPECT_TRUE(model.air.enabled);
  EXPECT_DOUBLE_EQ(model.air.temperature_c, 20.0);
  EXPECT_DOUBLE_EQ(model.air.humidity_percent, 50.0);
}

TEST(RoomModel, DefaultsOfOptionalKeys) {
  const RoomModel model = parseRoomModel(kMinimal);
  const AirConditions defaults;
  EXPECT_EQ(model.frame, "room");
  EXPECT_TRUE(model.has_ceiling);
  EXPECT_EQ(model.surfaces.at("ceiling").confidence, 1.0);
  EXPECT_TRUE(model.objects.empty());
  EXPECT_TRUE(model.inline_materials.empty());
  EXPECT_EQ(model.rig_position_m, Eigen::Vector3d::Zero());
  EXPECT_EQ(model.rig_rotation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(model.air.enabled, defaults.enabled);
  EXPECT_EQ(model.air.temperature_c, defaults.temperature_c);
  EXPECT_EQ(model.air.humidity_percent, defaults.humidity_percent);
  EXPECT_EQ(model.air.pressure_kpa, defaults.pressure_kpa);

  const RoomModel with_object = parseRoomModel(std::string(kMinimal) +
                                               "objects:\n  - {label: box, material: f, center_m: [1, 1, 0.5], size_m: [1, 1, 1]}\n");
  ASSERT_EQ(with_object.objects.size(), 1u);
  EXPECT_EQ(with_object.objects[0].yaw_rad, 0.0);
  EXPECT_EQ(with_object.objects[0].confidence, 1.0);
}

TEST(RoomModel, RoundTripsThroughYamlAndFiles) {
  RoomModel model = parseRoomModel(kDesignExample);
  // Values that need every digit, a name YAML would misread bare, a turned rig.
  model.objects.push_back({"shelf: tall", "wood_panel", {0.1 + 0.2, 1.0 / 3.0, 1.2}, {0.4, 1.8, 2.4}, -0.7853981633974483, 0.55});
  model.rig_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  model.air = {false, 12.5, 71.0, 99.1};
  model.inline_materials[0].source = "measured in situ, 2024";

  const std::string text = roomModelToYaml(model);
  const RoomModel back = parseRoomModel(text);
  EXPECT_EQ(back.frame, model.frame);
  EXPECT_EQ(back.size_m, model.size_m);
  EXPECT_EQ(back.has_ceiling, model.has_ceiling);
  ASSERT_EQ(back.surfaces.size(), model.surfaces.size());
  for (const auto& [name, surface] : model.surfaces) {
    EXPECT_EQ(back.surfaces.at(name).material, surface.material) << name;
    EXPECT_EQ(back.surfaces.at(name).confidence, surface.confidence) << name;
  }
  ASSERT_EQ(back.objects.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.objects[i].label, model.objects[i].label);
    EXPECT_EQ(back.objects[i].material, model.objects[i].material);
    EXPECT_EQ(back.objects[i].center_m, model.objects[i].center_m);  // exact: shortest round-trip decimals
    EXPECT_EQ(back.objects[i].size_m, model.objects[i].size_m);
    EXPECT_EQ(back.objects[i].yaw_rad, model.objects[i].yaw_rad);
    EXPECT_EQ(back.objects[i].confidence, model.objects[i].confidence);
  }
  ASSERT_EQ(back.inline_materials.size(), 1u);
  EXPECT_EQ(back.inline_materials[0].name, "my_panel");
  EXPECT_EQ(back.inline_materials[0].absorption, model.inline_materials[0].absorption);
  EXPECT_EQ(back.inline_materials[0].scattering, model.inline_materials[0].scattering);
  EXPECT_EQ(back.inline_materials[0].source, model.inline_materials[0].source);
  EXPECT_EQ(back.rig_position_m, model.rig_position_m);
  EXPECT_TRUE(back.rig_rotation.isApprox(model.rig_rotation, 1e-15));
  EXPECT_EQ(back.air.enabled, false);
  EXPECT_EQ(back.air.temperature_c, 12.5);
  EXPECT_EQ(back.air.humidity_percent, 71.0);
  EXPECT_EQ(back.air.pressure_kpa, 99.1);
  // Writing is a fixed point: the same model gives the same text.
  EXPECT_EQ(roomModelToYaml(back), text);
  // The compact layout of DESIGN.md.
  EXPECT_NE(text.find("  size_m: [6.64, 3.46, 2.67]\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  floor: {material: parquet_on_concrete, confidence: 0.9}\n"), std::string::npos) << text;
  EXPECT_NE(text.find("label: \"shelf: tall\""), std::string::npos) << text;

  const std::string path = tempPath("room.yaml").string();
  saveRoomModel(path, model);
  const RoomModel loaded = loadRoomModel(path);
  EXPECT_EQ(roomModelToYaml(loaded), text);
}

TEST(RoomModel, EmptyBoxMeshHasInwardFacesWithTheirMaterials) {
  const RoomModel model = parseRoomModel(kMinimal);
  const TriangleMesh mesh = roomModelToMesh(model);
  ASSERT_EQ(mesh.triangleCount(), 12u);
  const double x = 4.0, y = 3.0, z = 2.5;
  EXPECT_NEAR(mesh.totalArea(), 2.0 * (x * y + y * z + z * x), 1e-12);
  // Inward normals make the divergence-theorem volume negative.
  EXPECT_NEAR(signedVolume(mesh), -x * y * z, 1e-12);

  const std::map<std::string, Eigen::Vector3d> expected_normal = {
      {"f", Eigen::Vector3d::UnitZ()},   {"c", -Eigen::Vector3d::UnitZ()}, {"x0", Eigen::Vector3d::UnitX()},
      {"x1", -Eigen::Vector3d::UnitX()}, {"y0", Eigen::Vector3d::UnitY()}, {"y1", -Eigen::Vector3d::UnitY()}};
  const std::map<std::string, double> expected_area = {{"f", x * y},  {"c", x * y},  {"x0", y * z},
                                                       {"x1", y * z}, {"y0", x * z}, {"y1", x * z}};
  std::map<std::string, double> area;
  const Eigen::Vector3d centre(x / 2, y / 2, z / 2);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const std::string& name = mesh.material_names[mesh.triangle_material[t]];
    EXPECT_TRUE(mesh.normal(t).isApprox(expected_normal.at(name))) << name << ": " << mesh.normal(t).transpose();
    EXPECT_GT(mesh.normal(t).dot(centre - centroid(mesh, t)), 0.0) << name;
    area[name] += mesh.area(t);
  }
  for (const auto& [name, a] : expected_area) EXPECT_NEAR(area[name], a, 1e-12) << name;
  // The floor lies at z = 0 and the ceiling at z = size_z.
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const std::string& name = mesh.material_names[mesh.triangle_material[t]];
    if (name == "f") {
      EXPECT_NEAR(centroid(mesh, t).z(), 0.0, 1e-12);
    }
    if (name == "c") {
      EXPECT_NEAR(centroid(mesh, t).z(), z, 1e-12);
    }
  }
}

TEST(RoomModel, CourtyardHasNoCeiling) {
  // has_ceiling false: the ceiling entry may be left out, and an entry given is not meshed.
  std::string text = minimalWith("room_box: {size_m: [4, 3, 2.5]}", "room_box: {size_m: [4, 3, 2.5], has_ceiling: false}");
  text = text.replace(text.find("  ceiling: {material: c}\n"), std::string("  ceiling: {material: c}\n").size(), "");
  const RoomModel model = parseRoomModel(text);
  EXPECT_FALSE(model.has_ceiling);
  const TriangleMesh mesh = roomModelToMesh(model);
  ASSERT_EQ(mesh.triangleCount(), 10u);
  EXPECT_NEAR(mesh.totalArea(), 4.0 * 3.0 + 2.0 * (3.0 * 2.5 + 2.5 * 4.0), 1e-12);
  // Nothing faces down: the only downward face would be the ceiling.
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) EXPECT_GT(mesh.normal(t).z(), -0.5);
  EXPECT_EQ(std::count(mesh.material_names.begin(), mesh.material_names.end(), "c"), 0);
  EXPECT_NE(roomModelToYaml(model).find("has_ceiling: false"), std::string::npos);

  RoomModel with_entry = parseRoomModel(kMinimal);
  with_entry.has_ceiling = false;
  EXPECT_EQ(roomModelToMesh(with_entry).triangleCount(), 10u);
}

TEST(RoomModel, ObjectsAreClosedOutwardCuboidsTurnedByYaw) {
  RoomModel model = parseRoomModel(kMinimal);
  // 2 m long along its own x, 1 m deep, 1 m high, turned a quarter: 2 m along room y.
  model.objects.push_back({"cabinet", "wood", {2.0, 1.5, 0.5}, {2.0, 1.0, 1.0}, M_PI / 2, 1.0});
  const TriangleMesh mesh = roomModelToMesh(model);
  ASSERT_EQ(mesh.triangleCount(), 24u);
  const int wood = static_cast<int>(std::find(mesh.material_names.begin(), mesh.material_names.end(), "wood") -
                                    mesh.material_names.begin());
  TriangleMesh object;
  object.vertices = mesh.vertices;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.triangle_material[t] != wood) continue;
    object.triangles.push_back(mesh.triangles[t]);
    for (int k = 0; k < 3; ++k) {
      lo = lo.cwiseMin(mesh.vertices[mesh.triangles[t][k]]);
      hi = hi.cwiseMax(mesh.vertices[mesh.triangles[t][k]]);
    }
    // Outward: away from the object's centre.
    EXPECT_GT(mesh.normal(t).dot(centroid(mesh, t) - Eigen::Vector3d(2.0, 1.5, 0.5)), 0.0);
  }
  ASSERT_EQ(object.triangles.size(), 12u);
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3d(1.5, 0.5, 0.0), 1e-12)) << lo.transpose();
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3d(2.5, 2.5, 1.0), 1e-12)) << hi.transpose();
  EXPECT_NEAR(object.totalArea(), 2.0 * (2.0 * 1.0 + 1.0 * 1.0 + 1.0 * 2.0), 1e-12);
  EXPECT_NEAR(signedVolume(object), 2.0, 1e-12);  // closed, outward

  // At 45 degrees the corner at own (+1, +0.5) goes to centre + (cos - 0.5 sin, sin + 0.5 cos).
  model.objects[0].yaw_rad = M_PI / 4;
  const TriangleMesh turned = roomModelToMesh(model);
  const double c = std::cos(M_PI / 4), s = std::sin(M_PI / 4);
  const Eigen::Vector3d corner(2.0 + (1.0 * c - 0.5 * s), 1.5 + (1.0 * s + 0.5 * c), 1.0);
  bool found = false;
  for (const auto& v : turned.vertices) found = found || (v - corner).norm() < 1e-12;
  EXPECT_TRUE(found) << "no vertex at " << corner.transpose();
}

TEST(RoomModel, MaterialsForAddsInlineMaterialsAndRejectsUnknownNames) {
  MaterialLibrary library;
  for (const char* name : {"parquet_on_concrete", "plaster_smooth", "glass_thick", "brick_bare", "wood_panel"}) {
    library.add(flatMaterial(name, 0.1));
  }
  RoomModel model = parseRoomModel(kDesignExample);
  model.objects[0].material = "my_panel";  // an inline material in use
  const MaterialLibrary extended = materialsFor(model, library);
  EXPECT_EQ(extended.size(), library.size() + 1);
  EXPECT_DOUBLE_EQ(extended.get("my_panel").absorption[3], 0.5);
  EXPECT_FALSE(library.contains("my_panel"));  // the caller's library is left alone

  RoomModel unknown_surface = model;
  unknown_surface.surfaces["floor"].material = "lava";
  expectInputError([&] { materialsFor(unknown_surface, library); }, {"surfaces.floor.material", "lava"});
  RoomModel unknown_object = model;
  unknown_object.objects[0].material = "marble";
  expectInputError([&] { materialsFor(unknown_object, library); }, {"objects[0] (table).material", "marble"});
  // A courtyard's ceiling material is never used, so it need not exist.
  RoomModel courtyard = model;
  courtyard.has_ceiling = false;
  courtyard.surfaces["ceiling"].material = "sky";
  EXPECT_NO_THROW(materialsFor(courtyard, library));
}

TEST(RoomModel, BadInputNamesTheKeyAtFault) {
  expectInputError([] { loadRoomModel(tempPath("absent.yaml").string()); }, {"absent.yaml", "no such file"});
  expectInputError([] { parseRoomModel("room_box: {size_m: [1, 2, 3]\nsurfaces: [\n"); }, {"not valid YAML"});
  expectInputError([] { parseRoomModel("- just\n- a list\n"); }, {"not a room model"});
  expectInputError([] { parseRoomModel(minimalWith("[4, 3, 2.5]", "[4, -3, 2.5]")); },
                         {"room_box.size_m", "positive"});
  expectInputError([] { parseRoomModel(minimalWith("[4, 3, 2.5]", "[4, .nan, 2.5]")); },
                         {"room_box.size_m[1]", "finite"});
  expectInputError([] { parseRoomModel(minimalWith("[4, 3, 2.5]", "[4, 3]")); }, {"room_box.size_m", "3 numbers"});
  expectInputError([] { parseRoomModel(minimalWith("[4, 3, 2.5]", "[4, three, 2.5]")); },
                         {"room_box.size_m[1]", "'three' is not a number"});
  expectInputError([] { parseRoomModel(minimalWith("room_box: {size_m: [4, 3, 2.5]}", "room_box: {}")); },
                         {"room_box.size_m", "missing"});
  expectInputError([] { parseRoomModel(minimalWith("floor: {material: f}", "floor: {confidence: 0.5}")); },
                         {"surfaces.floor.material", "missing"});
  expectInputError([] { parseRoomModel(minimalWith("  ceiling: {material: c}\n", "")); },
                         {"surfaces.ceiling", "has_ceiling: false"});
  expectInputError([] { parseRoomModel(minimalWith("wall_y_max:", "wall_north:")); }, {"surfaces.wall_north", "unknown surface"});
  expectInputError([] { parseRoomModel(minimalWith("floor: {material: f}", "floor: {material: f, confidence: 1.5}")); },
                         {"surfaces.floor.confidence", "[0, 1]"});
  expectInputError(
      [] { parseRoomModel(std::string(kMinimal) + "objects:\n  - {label: box, material: f, center_m: [1, 1, 1], size_m: [1, 0, 1]}\n"); },
      {"objects[0] (box).size_m", "positive"});
  // A corrupt number that is finite but no place in a room (the ray tracer, in single
  // precision, would turn it into infinity).
  expectInputError(
      [] { parseRoomModel(std::string(kMinimal) + "objects:\n  - {label: box, material: f, center_m: [-1e308, 1, 1], size_m: [1, 1, 1]}\n"); },
      {"objects[0] (box).center_m", "1000 m outside"});
  expectInputError(
      [] { parseRoomModel(std::string(kMinimal) + "objects:\n  - {label: box, material: f, center_m: [1, 1, 1], size_m: [1, 1e30, 1]}\n"); },
      {"objects[0] (box).size_m", "at most 1000"});
  expectInputError([] { parseRoomModel(minimalWith("[4, 3, 2.5]", "[4, 3e12, 2.5]")); }, {"room_box.size_m", "not a room"});
  expectInputError(
      [] { parseRoomModel(std::string(kMinimal) + "objects:\n  - {label: box, center_m: [1, 1, 1], size_m: [1, 1, 1]}\n"); },
      {"objects[0] (box).material", "missing"});
  expectInputError(
      [] { parseRoomModel(std::string(kMinimal) + "materials:\n  m: {absorption: [0, 0, 0, 0, 0, 0, 0, 0, 1.2], scattering: [0, 0, 0, 0, 0, 0, 0, 0, 0]}\n"); },
      {"materials.m.absorption[8]", "outside [0, 1]"});
  expectInputError(
      [] { parseRoomModel(std::string(kMinimal) + "materials:\n  m: {absorption: [0.1, 0.2], scattering: [0, 0, 0, 0, 0, 0, 0, 0, 0]}\n"); },
      {"materials.m.absorption", "9 numbers"});
  expectInputError([] { parseRoomModel(std::string(kMinimal) + "rig_in_room: {rotation_xyzw: [1, 0, 0, 1]}\n"); },
                         {"rig_in_room.rotation_xyzw", "unit quaternion"});
  expectInputError([] { parseRoomModel(std::string(kMinimal) + "air: {humidity_percent: 120}\n"); },
                         {"air.humidity_percent", "[0, 100]"});
  expectInputError([] { parseRoomModel(std::string(kMinimal) + "air: {enabled: maybe}\n"); },
                         {"air.enabled", "true or false"});
  // The line of the fault is given where YAML knows it.
  expectInputError([] { parseRoomModel(minimalWith("floor: {material: f}", "floor: {material: f, confidence: -1}")); },
                         {"room model:3:"});

  // Models built in code are checked before they are meshed or written.
  RoomModel no_floor = parseRoomModel(kMinimal);
  no_floor.surfaces.erase("floor");
  expectInputError([&] { roomModelToMesh(no_floor); }, {"surfaces.floor.material"});
  expectInputError([&] { roomModelToYaml(no_floor); }, {"surfaces.floor.material"});
  RoomModel bad_confidence = parseRoomModel(kMinimal);
  bad_confidence.surfaces["wall_x_min"].confidence = 2.0;
  expectInputError([&] { roomModelToYaml(bad_confidence); }, {"surfaces.wall_x_min.confidence"});
  RoomModel nan_size = parseRoomModel(kMinimal);
  nan_size.size_m.z() = std::nan("");
  expectInputError([&] { roomModelToMesh(nan_size); }, {"room_box.size_m"});
  expectInputError([&] { saveRoomModel(tempPath("no_dir/room.yaml").string(), parseRoomModel(kMinimal)); },
                         {"room.yaml", "cannot open"});
}
