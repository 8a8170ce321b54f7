#pragma once
// A RoomScene message for the rostests: a box with a carpeted floor, a tiled ceiling and
// plastered walls, a source and a listener. Header-only: only ROS tests include it.
#include <room_reverb/RoomScene.h>

#include <Eigen/Core>
#include <string>

namespace room_reverb::test {

inline room_reverb::RoomScene shoeboxScene(const Eigen::Vector3d& size, const Eigen::Vector3d& source,
                                          const Eigen::Vector3d& listener, const std::string& mode) {
  room_reverb::RoomScene scene;
  scene.room.header.frame_id = "room";
  scene.room.size.x = size.x();
  scene.room.size.y = size.y();
  scene.room.size.z = size.z();
  scene.room.has_ceiling = true;
  scene.room.floor_material = "carpet_thick";
  scene.room.ceiling_material = "acoustic_ceiling_tiles";
  scene.room.wall_x_min_material = scene.room.wall_x_max_material = "plaster_smooth";
  scene.room.wall_y_min_material = scene.room.wall_y_max_material = "plaster_smooth";
  scene.source.x = source.x();
  scene.source.y = source.y();
  scene.source.z = source.z();
  scene.listener.x = listener.x();
  scene.listener.y = listener.y();
  scene.listener.z = listener.z();
  scene.mode = mode;
  return scene;
}

}  // namespace room_reverb::test
