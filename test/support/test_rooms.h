#pragma once
// Room models that several test files share.

namespace room_reverb::test {

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
