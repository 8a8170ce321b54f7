#include "room_reverb/diagnosis/model_extension.h"

#include <algorithm>
#include <set>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

bool surfaceUsed(const RoomModel& room, const std::string& name) {
  return room.surfaces.count(name) > 0 && (name != "ceiling" || room.has_ceiling);
}

// The materials a room model's surfaces and objects name.
std::set<std::string> usedMaterials(const RoomModel& room) {
  std::set<std::string> names;
  for (const auto& [name, surface] : room.surfaces) {
    if (surfaceUsed(room, name)) names.insert(surface.material);
  }
  for (const CuboidObject& object : room.objects) names.insert(object.material);
  return names;
}

double boxFaceArea(const Eigen::Vector3d& size, const std::string& surface) {
  if (surface == "floor" || surface == "ceiling") return size.x() * size.y();
  if (surface == "wall_x_min" || surface == "wall_x_max") return size.y() * size.z();
  return size.x() * size.z();
}

double cuboidArea(const Eigen::Vector3d& s) { return 2.0 * (s.x() * s.y() + s.y() * s.z() + s.x() * s.z()); }

}  // namespace

void ModelExtension::add(const ModelExtension& other) {
  if (other.air) air = other.air;
  for (const auto& [target, values] : other.absorption) absorption[target] = values;
  if (other.global_scattering) global_scattering = other.global_scattering;
  if (other.directivity) directivity = other.directivity;
  geometry_scale *= other.geometry_scale;
  reflectors.insert(reflectors.end(), other.reflectors.begin(), other.reflectors.end());
  if (other.coupled) coupled = other.coupled;
  if (other.modes) modes = other.modes;
  diffraction_scattering = diffraction_scattering || other.diffraction_scattering;
  wave_low_band = wave_low_band || other.wave_low_band;
  third_octave_bands = third_octave_bands || other.third_octave_bands;
}

RoomUnderTest RoomUnderTest::fromRoomModel(RoomModel room, MaterialLibrary library) {
  RoomUnderTest r;
  r.library_ = materialsFor(room, library);  // fails early for unknown materials
  r.air_ = room.air;
  r.room_ = std::move(room);
  roomModelToMesh(*r.room_);  // and for a malformed room
  return r;
}

RoomUnderTest RoomUnderTest::fromMesh(TriangleMesh mesh, MaterialLibrary library, AirConditions air) {
  if (mesh.triangleCount() == 0) throw InputError("the room has no surfaces (an empty mesh)");
  RoomUnderTest r;
  r.mesh_ = std::move(mesh);
  r.library_ = std::move(library);
  r.air_ = air;
  return r;
}

std::vector<std::string> RoomUnderTest::absorptionTargets() const {
  std::vector<std::string> targets;
  if (room_) {
    for (const char* name : kRoomSurfaceNames) {
      if (surfaceUsed(*room_, name)) targets.push_back(name);
    }
    for (const CuboidObject& object : room_->objects) {
      if (std::find(targets.begin(), targets.end(), object.label) == targets.end()) targets.push_back(object.label);
    }
  } else {
    targets = mesh_.material_names;
  }
  return targets;
}

OctaveBandValues RoomUnderTest::absorptionOf(const std::string& target) const {
  if (room_) {
    if (room_->surfaces.count(target) > 0) return library_.get(room_->surfaces.at(target).material).absorption;
    for (const CuboidObject& object : room_->objects) {
      if (object.label == target) return library_.get(object.material).absorption;
    }
    throw InputError("no surface or object named '" + target + "' in the room");
  }
  return library_.get(target).absorption;
}

double RoomUnderTest::areaOf(const std::string& target) const {
  if (room_) {
    if (room_->surfaces.count(target) > 0) return boxFaceArea(room_->size_m, target);
    double area = 0.0;
    for (const CuboidObject& object : room_->objects) area += object.label == target ? cuboidArea(object.size_m) : 0.0;
    return area;
  }
  double area = 0.0;
  for (std::size_t t = 0; t < mesh_.triangleCount(); ++t) {
    if (mesh_.material_names[static_cast<std::size_t>(mesh_.triangle_material[t])] == target) area += mesh_.area(t);
  }
  return area;
}

AirConditions RoomUnderTest::airWith(const ModelExtension& extension) const { return extension.air.value_or(air_); }

RoomModel RoomUnderTest::extendedRoomModel(const ModelExtension& extension) const {
  if (!room_) throw InputError("the room is a mesh; only a room model can be written with its corrections");
  RoomModel room = *room_;
  room.air = airWith(extension);
  const double k = extension.geometry_scale;
  room.size_m *= k;
  for (CuboidObject& object : room.objects) {
    object.center_m *= k;
    object.size_m *= k;
  }
  if (extension.global_scattering) {
    // Same-named inline materials replace the library's (materialsFor), so every surface
    // keeps its absorption and takes the fitted scattering.
    for (const std::string& name : usedMaterials(room)) {
      AcousticMaterial material = library_.get(name);
      material.name = name;
      material.scattering.fill(*extension.global_scattering);
      material.source = "scattering fitted by room_reverb diagnose";
      room.inline_materials.erase(std::remove_if(room.inline_materials.begin(), room.inline_materials.end(),
                                                 [&](const AcousticMaterial& m) { return m.name == name; }),
                                  room.inline_materials.end());
      room.inline_materials.push_back(material);
    }
  }
  const MaterialLibrary with_scattering = materialsFor(room, library_);
  for (const auto& [target, absorption] : extension.absorption) {
    const std::string fitted = target + "_fitted";
    std::string base;
    if (room.surfaces.count(target) > 0) {
      base = room.surfaces.at(target).material;
      room.surfaces[target].material = fitted;
    }
    for (CuboidObject& object : room.objects) {
      if (object.label != target) continue;
      base = object.material;
      object.material = fitted;
    }
    if (base.empty()) throw InputError("no surface or object named '" + target + "' in the room");
    AcousticMaterial material = with_scattering.get(base);
    material.name = fitted;
    material.absorption = absorption;
    material.source = "absorption fitted by room_reverb diagnose from " + base;
    room.inline_materials.push_back(material);
  }
  room.objects.insert(room.objects.end(), extension.reflectors.begin(), extension.reflectors.end());
  return room;
}

AcousticScene RoomUnderTest::scene(const ModelExtension& extension) const {
  if (room_) return roomModelToScene(extendedRoomModel(extension), library_);
  TriangleMesh mesh = mesh_;
  for (Eigen::Vector3d& v : mesh.vertices) v *= extension.geometry_scale;
  for (const CuboidObject& reflector : extension.reflectors) appendCuboid(mesh, reflector);
  MaterialOverrides overrides;
  overrides.absorption = extension.absorption;
  overrides.global_scattering = extension.global_scattering;
  return AcousticScene(std::move(mesh), library_, overrides, true);
}

}  // namespace room_reverb::core
