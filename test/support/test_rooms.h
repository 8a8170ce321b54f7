#pragma once
// Room models that several test files share.
#include <Eigen/Core>
#include <string>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::test {

// An upright cuboid of wood panel.
inline core::CuboidObject woodCuboid(const std::string& label, const Eigen::Vector3d& center, const Eigen::Vector3d& size,
                                     double yaw_rad = 0.0) {
  core::CuboidObject object;
  object.label = label;
  object.material = "wood_panel";
  object.center_m = center;
  object.size_m = size;
  object.yaw_rad = yaw_rad;
  return object;
}

// A plaster box of the given size with no objects, the rig at `rig`.
inline core::RoomModel plasterRoom(const Eigen::Vector3d& size, const Eigen::Vector3d& rig = Eigen::Vector3d::Zero()) {
  core::RoomModel model;
  model.size_m = size;
  for (const char* name : core::kRoomSurfaceNames) model.surfaces[name] = {"plaster_smooth", 1.0};
  model.rig_position_m = rig;
  return model;
}

// A 7 x 5 x 3.2 m room whose absorption sits on the floor (thick carpet) and the ceiling
// (tiles) between hard, hardly scattering walls (plaster, one painted concrete): its
// lasting sound travels between the walls, far longer than Eyring's mean allows.
inline core::RoomModel unevenAbsorptionRoom() {
  core::RoomModel room;
  room.size_m = {7.0, 5.0, 3.2};
  for (const char* name : core::kRoomSurfaceNames) room.surfaces[name] = {"plaster_smooth", 1.0};
  room.surfaces["floor"] = {"carpet_thick", 1.0};
  room.surfaces["ceiling"] = {"acoustic_ceiling_tiles", 1.0};
  room.surfaces["wall_y_min"] = {"concrete_painted", 1.0};
  return room;
}

// A 5 x 4 x 3 m studio of library materials (carpet, ceiling tiles, plaster, glass,
// plasterboard) with air at 20 C / 50 %: low scattering, absorbing floor and ceiling.
inline constexpr const char* kStudioRoomYaml = R"(frame: room
room_box: {size_m: [5.0, 4.0, 3.0], has_ceiling: true}
surfaces:
  floor: {material: carpet_on_concrete}
  ceiling: {material: acoustic_ceiling_tiles}
  wall_x_min: {material: plaster_smooth}
  wall_x_max: {material: plaster_smooth}
  wall_y_min: {material: glass_window}
  wall_y_max: {material: plasterboard_on_studs}
air: {enabled: true, temperature_c: 20, humidity_percent: 50}
)";

}  // namespace room_reverb::test
