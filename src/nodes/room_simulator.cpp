// room_simulator: offers ~simulate (room_reverb/SimulateRoom), the impulse response of a
// room model or mesh by image sources and ray tracing. Parameters: config/room_simulator.yaml.
#include <ros/ros.h>

#include "room_reverb/ros/simulation_server.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "room_simulator");
  ros::NodeHandle private_nh("~");
  try {
    room_reverb::ros_bridge::SimulationServer server(private_nh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("room_simulator: %s", e.what());
    return 2;
  }
  return 0;
}
