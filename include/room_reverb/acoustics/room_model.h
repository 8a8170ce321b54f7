#pragma once
// The room model of DESIGN.md (room.yaml; the RoomModel message): a room box whose inside
// faces are floor, ceiling and walls, labelled cuboid objects, materials and the rig pose.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <map>
#include <string>
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/air_absorption.h"
#include "room_reverb/acoustics/cuboid.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/triangle_mesh.h"

namespace room_reverb::core {

struct SurfaceAssignment {
  std::string material;
  double confidence = 1.0;
  // Optional: the material the surface could otherwise be and its confidence (the visual
  // route's second choice). Informative only; the simulation uses `material`.
  std::string runner_up{};
  double runner_up_confidence = 0.0;
  // The scattering the surface's relief adds per octave band, 63 Hz-16 kHz (what stands
  // on it or is set into it and is no object of the model; acoustics/relief_scattering.h),
  // combined with the material's own as 1 - (1 - s_m)(1 - s_r). Zero: a plane face.
  OctaveBandValues relief_scattering{};
};

// Names of the six box faces, as in room.yaml.
extern const std::array<const char*, 6> kRoomSurfaceNames;  // floor, ceiling, wall_x_min, wall_x_max, wall_y_min, wall_y_max

struct RoomModel {
  std::string frame = "room";
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();  // inner extent; box spans [0, size]
  bool has_ceiling = true;
  std::map<std::string, SurfaceAssignment> surfaces;  // keyed by kRoomSurfaceNames
  std::vector<CuboidObject> objects;
  std::vector<AcousticMaterial> inline_materials;
  Eigen::Vector3d rig_position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rig_rotation = Eigen::Quaterniond::Identity();
  AirConditions air;
};

// Parse / write room.yaml. Throws InputError (with the key at fault) for missing or
// malformed keys, non-positive sizes, non-finite numbers, a surface without a material.
RoomModel loadRoomModel(const std::string& path);
RoomModel parseRoomModel(const std::string& yaml_text);
std::string roomModelToYaml(const RoomModel& model);
void saveRoomModel(const std::string& path, const RoomModel& model);

// The room as triangles: the box's faces with normals pointing into the room (the ceiling
// left out when has_ceiling is false), each object as a closed cuboid with outward
// normals, rotated by its yaw about its centre. Triangle materials are the assigned
// material names.
TriangleMesh roomModelToMesh(const RoomModel& model);
// One object's closed cuboid (outward normals, yaw about its centre) added to a mesh.
void appendCuboid(TriangleMesh& mesh, const CuboidObject& object);

// The library extended by the model's inline materials; throws InputError if a surface or
// object names a material neither defines.
MaterialLibrary materialsFor(const RoomModel& model, const MaterialLibrary& library);

// The relief of each used box face and each object: its triangles in roomModelToMesh's
// mesh and its relief_scattering; faces in kRoomSurfaceNames order, then the objects.
std::vector<SurfaceRelief> surfaceReliefs(const RoomModel& model);

// The scene the simulator traces: the model's mesh with its materials (library plus inline
// ones; each face's and object's relief scattering combined with its material's), closed unless the
// room has no ceiling, and the model's box and objects as its room shape (inside tests
// and volume exact, objects named in errors). The model's air
// conditions are not part of the scene; the caller passes model.air to the simulation.
AcousticScene roomModelToScene(const RoomModel& model, const MaterialLibrary& library,
                               const MaterialOverrides& overrides = {});

}  // namespace room_reverb::core
