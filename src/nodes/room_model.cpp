// room_model: offers ~build (room_reverb/BuildRoomModel), the room as labelled cuboids with
// materials from the latest point cloud and image, or from a stereo pair in the request
// (ros/room_model_server.h). Parameters: config/room_model.yaml.
#include <ros/ros.h>

#include "room_reverb/common/memory_reuse.h"
#include "room_reverb/ros/room_model_server.h"

int main(int argc, char** argv) {
  room_reverb::core::keepFreedMemoryForReuse();
  ros::init(argc, argv, "room_model");
  try {
    room_reverb::ros_bridge::RoomModelServer server{ros::NodeHandle(), ros::NodeHandle("~")};
    // Two threads: a build (a second or two) does not hold up the subscriptions.
    ros::AsyncSpinner spinner(2);
    spinner.start();
    ros::waitForShutdown();
  } catch (const std::exception& e) {
    ROS_FATAL("room_model: %s", e.what());
    return 2;
  }
  return 0;
}
