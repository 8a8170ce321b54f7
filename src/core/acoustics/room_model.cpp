#include "room_reverb/acoustics/room_model.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>
#include <tuple>
#include <utility>

#include "room_reverb/acoustics/relief_scattering.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"

namespace room_reverb::core {

const std::array<const char*, 6> kRoomSurfaceNames = {"floor",      "ceiling",    "wall_x_min",
                                                      "wall_x_max", "wall_y_min", "wall_y_max"};

namespace {

// Corner c of a box is (c & 1, c & 2, c & 4) along (x, y, z), 0 for the low side.
// Each face is listed in kRoomSurfaceNames order, wound counter-clockwise as seen from
// inside the box, so its right-hand normal points into the room.
constexpr std::array<std::array<int, 4>, 6> kBoxFacesInward = {{
    {0, 1, 3, 2},  // floor (z = 0), normal +z
    {4, 6, 7, 5},  // ceiling (z = max), normal -z
    {0, 2, 6, 4},  // wall_x_min, normal +x
    {1, 5, 7, 3},  // wall_x_max, normal -x
    {0, 4, 5, 1},  // wall_y_min, normal +y
    {2, 3, 7, 6},  // wall_y_max, normal -y
}};

Eigen::Vector3d boxCorner(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int c) {
  return {(c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z()};
}

void appendQuad(TriangleMesh& mesh, const std::array<int, 4>& q, bool inward, int material) {
  if (inward) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  } else {
    mesh.triangles.push_back({q[0], q[2], q[1]});
    mesh.triangles.push_back({q[0], q[3], q[2]});
  }
  mesh.triangle_material.push_back(material);
  mesh.triangle_material.push_back(material);
}

bool isSurfaceName(const std::string& name) {
  for (const char* known : kRoomSurfaceNames) {
    if (name == known) return true;
  }
  return false;
}

bool surfaceIsUsed(const RoomModel& model, const std::string& name) {
  return model.has_ceiling || name != "ceiling";
}

std::string objectKey(std::size_t index, const std::string& label) {
  return "objects[" + std::to_string(index) + "]" + (label.empty() ? "" : " (" + label + ")");
}

constexpr double kLargestRoomM = 1000.0;

// Checks what a RoomModel must satisfy however it was made (parsed or built in code), with
// the key of room.yaml that holds the fault.
void checkModel(const RoomModel& model, const std::string& source) {
  auto fail = [&](const std::string& key, const std::string& message) {
    throw InputError(source + ": " + key + ": " + message);
  };
  if (!model.size_m.allFinite() || (model.size_m.array() <= 0.0).any()) {
    std::ostringstream os;
    os << "must be three positive, finite lengths in metres (got " << model.size_m.transpose() << ")";
    fail("room_box.size_m", os.str());
  }
  // Lengths and places beyond kLargestRoomM are not a room but a corrupt file: the ray
  // tracer works in single precision, where a finite 1e308 becomes infinite and its rays
  // invalid.
  const std::string largest = std::to_string(static_cast<int>(kLargestRoomM));
  const auto within = [&](const Eigen::Vector3d& point) {
    return (point.array() >= -kLargestRoomM).all() && (point.array() <= model.size_m.array() + kLargestRoomM).all();
  };
  if ((model.size_m.array() > kLargestRoomM).any()) {
    fail("room_box.size_m", "a side longer than " + largest + " m is not a room");
  }
  if (model.frame.empty()) fail("frame", "must be a frame name (room)");
  auto checkConfidence = [&](double confidence, const std::string& key) {
    if (!(confidence >= 0.0 && confidence <= 1.0)) fail(key + ".confidence", "must be in [0, 1]");
  };
  auto checkRelief = [&](const OctaveBandValues& relief, const std::string& key) {
    for (double s : relief) {
      if (!(s >= 0.0 && s <= 1.0)) fail(key + ".relief_scattering", "coefficients must be in [0, 1]");
    }
  };
  for (const char* name : kRoomSurfaceNames) {
    if (!surfaceIsUsed(model, name)) continue;
    const auto it = model.surfaces.find(name);
    if (it == model.surfaces.end() || it->second.material.empty()) {
      fail(std::string("surfaces.") + name + ".material", "missing: every face of the box needs a material name");
    }
  }
  for (const auto& [name, surface] : model.surfaces) {
    if (!isSurfaceName(name)) fail("surfaces." + name, "unknown surface");
    checkConfidence(surface.confidence, "surfaces." + name);
    if (!(surface.runner_up_confidence >= 0.0 && surface.runner_up_confidence <= 1.0)) {
      fail("surfaces." + name + ".runner_up_confidence", "must be in [0, 1]");
    }
    checkRelief(surface.relief_scattering, "surfaces." + name);
  }
  for (std::size_t i = 0; i < model.objects.size(); ++i) {
    const CuboidObject& object = model.objects[i];
    const std::string key = objectKey(i, object.label);
    if (object.label.empty()) fail(key + ".label", "missing");
    if (object.material.empty()) fail(key + ".material", "missing");
    if (!object.center_m.allFinite()) fail(key + ".center_m", "must be finite");
    if (!within(object.center_m)) fail(key + ".center_m", "lies more than " + largest + " m outside the room box");
    if (!object.size_m.allFinite() || (object.size_m.array() <= 0.0).any() ||
        (object.size_m.array() > kLargestRoomM).any()) {
      fail(key + ".size_m", "must be three positive, finite lengths in metres, at most " + largest);
    }
    if (!std::isfinite(object.yaw_rad)) fail(key + ".yaw_rad", "must be finite");
    checkRelief(object.relief_scattering, key);
    checkConfidence(object.confidence, key);
    if (!(object.runner_up_confidence >= 0.0 && object.runner_up_confidence <= 1.0)) fail(key + ".runner_up_confidence", "must be in [0, 1]");
  }
  for (const AcousticMaterial& material : model.inline_materials) {
    if (material.name.empty()) fail("materials", "an inline material has no name");
    for (std::size_t b = 0; b < material.absorption.size(); ++b) {
      if (!(material.absorption[b] >= 0.0 && material.absorption[b] <= 1.0) ||
          !(material.scattering[b] >= 0.0 && material.scattering[b] <= 1.0)) {
        fail("materials." + material.name, "coefficients must be in [0, 1]");
      }
    }
  }
  if (!model.rig_position_m.allFinite()) fail("rig_in_room.position_m", "must be finite");
  if (!within(model.rig_position_m)) fail("rig_in_room.position_m", "lies more than " + largest + " m outside the room box");
  if (!model.rig_rotation.coeffs().allFinite() || std::abs(model.rig_rotation.norm() - 1.0) > 1e-3) {
    fail("rig_in_room.rotation_xyzw", "must be a unit quaternion");
  }
  const AirConditions& air = model.air;
  if (!std::isfinite(air.temperature_c) || air.temperature_c <= -273.15) fail("air.temperature_c", "must be above absolute zero");
  if (!(air.humidity_percent >= 0.0 && air.humidity_percent <= 100.0)) fail("air.humidity_percent", "must be in [0, 100]");
  if (!(air.pressure_kpa > 0.0) || !std::isfinite(air.pressure_kpa)) fail("air.pressure_kpa", "must be positive");
}

// ---------------------------------------------------------------------------------------
// Reading: each accessor names the key it reads, and the line when yaml-cpp knows it.
// ---------------------------------------------------------------------------------------

class Reader : public YamlReader {
 public:
  using YamlReader::YamlReader;

  Eigen::Vector3d positiveSize(const YAML::Node& node, const std::string& key) const {
    const Eigen::Vector3d size = vector3(node, key);
    for (int i = 0; i < 3; ++i) {
      if (size[i] <= 0.0) {
        fail(node, key, "every extent must be positive (got " + node[static_cast<std::size_t>(i)].Scalar() + ")");
      }
    }
    return size;
  }

  double confidenceOr(const YAML::Node& parent, const std::string& key, const std::string& name = "confidence",
                      double fallback = 1.0) const {
    const double value = numberOr(parent, name, key + "." + name, fallback);
    if (value < 0.0 || value > 1.0) fail(parent[name], key + "." + name, "must be in [0, 1]");
    return value;
  }

  // The optional runner_up and runner_up_confidence of a surface or object (the second
  // one only with the first).
  std::pair<std::string, double> runnerUp(const YAML::Node& parent, const std::string& key) const {
    const std::string name = textOr(parent, "runner_up", key + ".runner_up", "");
    if (name.empty() && parent["runner_up_confidence"].IsDefined()) {
      fail(parent["runner_up_confidence"], key + ".runner_up_confidence", "given without runner_up");
    }
    return {name, name.empty() ? 0.0 : confidenceOr(parent, key, "runner_up_confidence", 0.0)};
  }

  // The optional relief_scattering of a surface or object; zero where absent.
  OctaveBandValues reliefOr(const YAML::Node& parent, const std::string& key) const {
    const YAML::Node node = parent["relief_scattering"];
    return node.IsDefined() ? bandCoefficients(node, key + ".relief_scattering") : OctaveBandValues{};
  }

  OctaveBandValues bandCoefficients(const YAML::Node& node, const std::string& key) const {
    const auto v = numbers(node, key, kOctaveBandCount);
    OctaveBandValues out{};
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (v[i] < 0.0 || v[i] > 1.0) {
        fail(node, key + "[" + std::to_string(i) + "]", "coefficient " + node[i].Scalar() + " is outside [0, 1]");
      }
      out[i] = v[i];
    }
    return out;
  }

  RoomModel parse(const std::string& yaml_text) const {
    return guarded("room model", [&] { return parseUnguarded(yaml_text); });
  }

 private:
  RoomModel parseUnguarded(const std::string& yaml_text) const {
    const YAML::Node root = loadMap(yaml_text, "a room model with room_box and surfaces");

    RoomModel model;
    if (root["frame"].IsDefined()) model.frame = text(root["frame"], "frame");

    const YAML::Node box = require(root, "room_box", "room_box");
    requireMap(box, "room_box");
    model.size_m = positiveSize(require(box, "size_m", "room_box.size_m"), "room_box.size_m");
    model.has_ceiling = flagOr(box, "has_ceiling", "room_box.has_ceiling", true);

    const YAML::Node surfaces = require(root, "surfaces", "surfaces");
    requireMap(surfaces, "surfaces");
    for (const auto& entry : surfaces) {
      const std::string name = entry.first.as<std::string>();
      const std::string key = "surfaces." + name;
      if (!isSurfaceName(name)) {
        // A misspelt face would otherwise leave the real face without a material.
        fail(entry.first, key, "unknown surface (use floor, ceiling, wall_x_min, wall_x_max, wall_y_min, wall_y_max)");
      }
      requireMap(entry.second, key);
      SurfaceAssignment assignment;
      assignment.material = text(require(entry.second, "material", key + ".material",
                                         "missing: every face of the box needs a material name"),
                                 key + ".material");
      assignment.confidence = confidenceOr(entry.second, key);
      std::tie(assignment.runner_up, assignment.runner_up_confidence) = runnerUp(entry.second, key);
      assignment.relief_scattering = reliefOr(entry.second, key);
      model.surfaces[name] = assignment;
    }
    for (const char* name : kRoomSurfaceNames) {
      if (surfaceIsUsed(model, name) && model.surfaces.count(name) == 0) {
        fail(surfaces, std::string("surfaces.") + name,
             std::string("missing: every face of the box needs a material") +
                 (std::string(name) == "ceiling" ? " (or set room_box.has_ceiling: false)" : ""));
      }
    }

    const YAML::Node objects = root["objects"];
    if (objects.IsDefined() && !objects.IsNull()) {
      if (!objects.IsSequence()) fail(objects, "objects", "must be a list");
      for (std::size_t i = 0; i < objects.size(); ++i) {
        const YAML::Node node = objects[i];
        std::string key = objectKey(i, "");
        requireMap(node, key);
        CuboidObject object;
        object.label = text(require(node, "label", key + ".label"), key + ".label");
        key = objectKey(i, object.label);
        object.material = text(require(node, "material", key + ".material"), key + ".material");
        object.center_m = vector3(require(node, "center_m", key + ".center_m"), key + ".center_m");
        object.size_m = positiveSize(require(node, "size_m", key + ".size_m"), key + ".size_m");
        object.yaw_rad = numberOr(node, "yaw_rad", key + ".yaw_rad", 0.0);
        object.confidence = confidenceOr(node, key);
        std::tie(object.runner_up, object.runner_up_confidence) = runnerUp(node, key);
        object.relief_scattering = reliefOr(node, key);
        model.objects.push_back(object);
      }
    }

    const YAML::Node materials = root["materials"];
    if (materials.IsDefined() && !materials.IsNull()) {
      requireMap(materials, "materials");
      for (const auto& entry : materials) {
        AcousticMaterial material;
        material.name = entry.first.as<std::string>();
        const std::string key = "materials." + material.name;
        requireMap(entry.second, key);
        material.absorption = bandCoefficients(require(entry.second, "absorption", key + ".absorption"), key + ".absorption");
        material.scattering = bandCoefficients(require(entry.second, "scattering", key + ".scattering"), key + ".scattering");
        if (entry.second["source"].IsDefined()) material.source = text(entry.second["source"], key + ".source");
        model.inline_materials.push_back(material);
      }
    }

    const YAML::Node rig = root["rig_in_room"];
    if (rig.IsDefined() && !rig.IsNull()) {
      requireMap(rig, "rig_in_room");
      if (rig["position_m"].IsDefined()) model.rig_position_m = vector3(rig["position_m"], "rig_in_room.position_m");
      if (rig["rotation_xyzw"].IsDefined()) {
        const auto q = numbers(rig["rotation_xyzw"], "rig_in_room.rotation_xyzw", 4);
        const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
        // Rounded decimals are fine; anything far from unit length is a mistake (Euler
        // angles, w first), not something to normalise away.
        if (std::abs(rotation.norm() - 1.0) > 1e-3) {
          fail(rig["rotation_xyzw"], "rig_in_room.rotation_xyzw",
               "must be a unit quaternion in x, y, z, w order (norm is " + std::to_string(rotation.norm()) + ")");
        }
        // Renormalised only when visibly off, so that a unit quaternion written with
        // round-trip decimals reads back bit for bit.
        model.rig_rotation = std::abs(rotation.norm() - 1.0) > 1e-12 ? rotation.normalized() : rotation;
      }
    }

    const YAML::Node air = root["air"];
    if (air.IsDefined() && !air.IsNull()) {
      requireMap(air, "air");
      model.air.enabled = flagOr(air, "enabled", "air.enabled", model.air.enabled);
      model.air.temperature_c = numberOr(air, "temperature_c", "air.temperature_c", model.air.temperature_c);
      model.air.humidity_percent = numberOr(air, "humidity_percent", "air.humidity_percent", model.air.humidity_percent);
      model.air.pressure_kpa = numberOr(air, "pressure_kpa", "air.pressure_kpa", model.air.pressure_kpa);
      if (model.air.temperature_c <= -273.15) fail(air["temperature_c"], "air.temperature_c", "is below absolute zero");
      if (model.air.humidity_percent < 0.0 || model.air.humidity_percent > 100.0) {
        fail(air["humidity_percent"], "air.humidity_percent", "must be in [0, 100]");
      }
      if (model.air.pressure_kpa <= 0.0) fail(air["pressure_kpa"], "air.pressure_kpa", "must be positive");
    }

    checkModel(model, source());
    return model;
  }
};

// ---------------------------------------------------------------------------------------
// Writing: by hand rather than with YAML::Emitter, to keep the compact layout of DESIGN.md
// (one flow map per surface and object) and the shortest decimals that read back exactly.
// ---------------------------------------------------------------------------------------

std::string number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string numberList(const double* values, std::size_t count) {
  std::string out = "[";
  for (std::size_t i = 0; i < count; ++i) out += (i ? ", " : "") + number(values[i]);
  return out + "]";
}

std::string vectorText(const Eigen::Vector3d& v) { return numberList(v.data(), 3); }

// Names stay bare when they are plain words; anything YAML could read differently (flow
// punctuation, a colon, a null keyword, an empty string) is double-quoted.
std::string nameText(const std::string& name) {
  bool plain = !name.empty() && name != "null" && name != "Null" && name != "NULL" && name != "~";
  for (const char ch : name) {
    const bool ok = std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.' || ch == '/';
    plain = plain && ok;
  }
  if (plain && name.front() == '-') plain = false;
  if (plain) return name;
  std::string out = "\"";
  for (const char ch : name) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}

// The optional runner-up keys of a surface or object, after its confidence.
std::string runnerUpText(const std::string& runner_up, double confidence) {
  if (runner_up.empty()) return "";
  return ", runner_up: " + nameText(runner_up) + ", runner_up_confidence: " + number(confidence);
}

// The optional relief key of a surface or object, written only where there is a relief.
std::string reliefText(const OctaveBandValues& relief) {
  if (!hasRelief(relief)) return "";
  return ", relief_scattering: " + numberList(relief.data(), relief.size());
}

}  // namespace

RoomModel parseRoomModel(const std::string& yaml_text) { return Reader("room model").parse(yaml_text); }

RoomModel loadRoomModel(const std::string& path) { return Reader(path).parse(readTextFile(path, "room model")); }

std::string roomModelToYaml(const RoomModel& model) {
  // A model that would not read back is refused here rather than written.
  checkModel(model, "room model");
  std::ostringstream out;
  out << "# room_reverb room model (DESIGN.md, room.yaml); metres, radians, room frame z up\n";
  out << "frame: " << nameText(model.frame) << "\n";
  out << "room_box:\n";
  out << "  size_m: " << vectorText(model.size_m) << "\n";
  out << "  has_ceiling: " << (model.has_ceiling ? "true" : "false") << "\n";
  out << "surfaces:\n";
  for (const char* name : kRoomSurfaceNames) {
    const auto it = model.surfaces.find(name);
    if (it == model.surfaces.end()) continue;  // only an unused ceiling can be absent
    out << "  " << name << ": {material: " << nameText(it->second.material)
        << ", confidence: " << number(it->second.confidence) << runnerUpText(it->second.runner_up, it->second.runner_up_confidence)
        << reliefText(it->second.relief_scattering) << "}\n";
  }
  if (model.objects.empty()) {
    out << "objects: []\n";
  } else {
    out << "objects:\n";
    for (const CuboidObject& object : model.objects) {
      out << "  - {label: " << nameText(object.label) << ", material: " << nameText(object.material)
          << ", center_m: " << vectorText(object.center_m) << ", size_m: " << vectorText(object.size_m)
          << ", yaw_rad: " << number(object.yaw_rad) << ", confidence: " << number(object.confidence)
          << runnerUpText(object.runner_up, object.runner_up_confidence) << reliefText(object.relief_scattering) << "}\n";
    }
  }
  if (!model.inline_materials.empty()) {
    out << "materials:\n";
    for (const AcousticMaterial& material : model.inline_materials) {
      out << "  " << nameText(material.name) << ": {absorption: "
          << numberList(material.absorption.data(), material.absorption.size())
          << ", scattering: " << numberList(material.scattering.data(), material.scattering.size());
      if (!material.source.empty()) out << ", source: " << nameText(material.source);
      out << "}\n";
    }
  }
  const Eigen::Quaterniond& q = model.rig_rotation;
  const double xyzw[4] = {q.x(), q.y(), q.z(), q.w()};
  out << "rig_in_room: {position_m: " << vectorText(model.rig_position_m)
      << ", rotation_xyzw: " << numberList(xyzw, 4) << "}\n";
  out << "air: {enabled: " << (model.air.enabled ? "true" : "false")
      << ", temperature_c: " << number(model.air.temperature_c)
      << ", humidity_percent: " << number(model.air.humidity_percent)
      << ", pressure_kpa: " << number(model.air.pressure_kpa) << "}\n";
  return out.str();
}

void saveRoomModel(const std::string& path, const RoomModel& model) { writeTextFile(path, roomModelToYaml(model)); }

// A closed cuboid seen from outside, turned by its yaw about a vertical axis through its
// centre.
void appendCuboid(TriangleMesh& mesh, const CuboidObject& object) {
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(object.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d half = 0.5 * object.size_m;
  const int base = static_cast<int>(mesh.vertices.size());
  for (int c = 0; c < 8; ++c) mesh.vertices.push_back(object.center_m + yaw * boxCorner(-half, half, c));
  const int material = mesh.materialIndex(object.material);
  for (const auto& face : kBoxFacesInward) {
    appendQuad(mesh, {face[0] + base, face[1] + base, face[2] + base, face[3] + base}, false, material);
  }
}

TriangleMesh roomModelToMesh(const RoomModel& model) {
  checkModel(model, "room model");
  TriangleMesh mesh;

  // The box: eight shared corners, faces wound to face inwards.
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  for (int c = 0; c < 8; ++c) mesh.vertices.push_back(boxCorner(zero, model.size_m, c));
  for (std::size_t f = 0; f < kRoomSurfaceNames.size(); ++f) {
    const std::string name = kRoomSurfaceNames[f];
    if (!surfaceIsUsed(model, name)) continue;  // a courtyard's top is open sky
    appendQuad(mesh, kBoxFacesInward[f], true, mesh.materialIndex(model.surfaces.at(name).material));
  }

  for (const CuboidObject& object : model.objects) appendCuboid(mesh, object);
  validateMesh(mesh, "room model");
  return mesh;
}

MaterialLibrary materialsFor(const RoomModel& model, const MaterialLibrary& library) {
  MaterialLibrary result = library;
  for (const AcousticMaterial& material : model.inline_materials) {
    try {
      result.add(material);
    } catch (const InputError& e) {
      throw InputError("materials." + material.name + ": " + e.what());
    }
  }
  // get() resolves aliases and, for an unknown name, suggests close matches.
  for (const auto& [name, assignment] : model.surfaces) {
    if (!surfaceIsUsed(model, name)) continue;
    try {
      result.get(assignment.material);
    } catch (const InputError& e) {
      throw InputError("surfaces." + name + ".material: " + e.what());
    }
  }
  for (std::size_t i = 0; i < model.objects.size(); ++i) {
    try {
      result.get(model.objects[i].material);
    } catch (const InputError& e) {
      throw InputError(objectKey(i, model.objects[i].label) + ".material: " + e.what());
    }
  }
  return result;
}

std::vector<SurfaceRelief> surfaceReliefs(const RoomModel& model) {
  std::vector<SurfaceRelief> reliefs;
  std::size_t first_triangle = 0;  // roomModelToMesh: two triangles per used face, in order, first
  for (const char* name : kRoomSurfaceNames) {
    if (!surfaceIsUsed(model, name)) continue;
    reliefs.push_back({name, {first_triangle, first_triangle + 1}, model.surfaces.at(name).relief_scattering});
    first_triangle += 2;
  }
  for (std::size_t i = 0; i < model.objects.size(); ++i) {  // then twelve per object (appendCuboid)
    SurfaceRelief relief{objectKey(i, model.objects[i].label), {}, model.objects[i].relief_scattering};
    for (std::size_t t = 0; t < 12; ++t) relief.triangles.push_back(first_triangle + t);
    reliefs.push_back(std::move(relief));
    first_triangle += 12;
  }
  return reliefs;
}

AcousticScene roomModelToScene(const RoomModel& model, const MaterialLibrary& library,
                               const MaterialOverrides& overrides) {
  RoomShape shape;
  shape.size_m = model.size_m;
  shape.has_ceiling = model.has_ceiling;
  shape.objects = model.objects;
  return AcousticScene(roomModelToMesh(model), materialsFor(model, library), overrides, std::move(shape),
                       surfaceReliefs(model));
}

}  // namespace room_reverb::core
