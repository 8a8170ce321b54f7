#pragma once
// A scene's own room as the layout the material step starts from: materials cleared,
// objects fully trusted, the rig where the scene puts it.
#include <Eigen/Geometry>

#include "room_reverb/vision/room_layout.h"

namespace room_reverb::test {

inline core::RoomLayout trueLayout(const core::RoomModel& room) {
  core::RoomLayout layout;
  layout.model = room;
  for (auto& [name, surface] : layout.model.surfaces) surface = {"", 0.0};
  for (core::CuboidObject& object : layout.model.objects) {
    object.material.clear();
    object.confidence = 1.0;
  }
  layout.room_from_rig = Eigen::Translation3d(room.rig_position_m) * room.rig_rotation;
  return layout;
}

}  // namespace room_reverb::test
