#pragma once
// The SimulateRoom service over the core's simulation engine.
#include <ros/ros.h>
#include <room_reverb/SimulateRoom.h>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_simulation.h"

namespace room_reverb::ros_bridge {

// Answers ~simulate. Parameters are read once, at construction, and checked loudly
// (config/room_simulator.yaml documents them). Never throws across ROS: bad input gives
// success=false and a message.
class SimulationServer {
 public:
  explicit SimulationServer(::ros::NodeHandle& private_nh);

  // The service body, callable without ROS for tests.
  bool simulate(room_reverb::SimulateRoom::Request& request, room_reverb::SimulateRoom::Response& response);

 private:
  core::SimulationSettings defaults_;
  int max_rays_ = 0;  // a request for more rays is refused
  core::MaterialLibrary library_;
  ::ros::ServiceServer server_;
};

}  // namespace room_reverb::ros_bridge
