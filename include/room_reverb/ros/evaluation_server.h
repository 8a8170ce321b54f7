#pragma once
// The evaluation node's services over the core's comparison and diagnosis (issue 8):
// ~compare (room_reverb/CompareMeasurement) and ~diagnose (room_reverb/DiagnoseRoom).
// A diagnosis of a room model also publishes the corrected room, latched, on
// ~corrected_room (room_reverb/RoomModel): what the simulator and the renderer should use
// from then on (the live system's closed loop).
#include <ros/ros.h>
#include <room_reverb/CompareMeasurement.h>
#include <room_reverb/DiagnoseRoom.h>

#include <string>

#include "room_reverb/acoustics/material.h"

namespace room_reverb::ros_bridge {

class EvaluationServer {
 public:
  // Parameters (config/evaluation.yaml) are read once and checked loudly.
  explicit EvaluationServer(::ros::NodeHandle& private_nh);

  // The service bodies, callable without ROS for tests. Never throw: bad input gives
  // success=false and a message.
  bool compare(room_reverb::CompareMeasurement::Request& request, room_reverb::CompareMeasurement::Response& response);
  bool diagnose(room_reverb::DiagnoseRoom::Request& request, room_reverb::DiagnoseRoom::Response& response);

 private:
  int rays_ = 20000;           // compare
  int diagnosis_rays_ = 10000;
  int seed_ = 1;
  int max_causes_ = 3;
  int threads_ = 0;
  std::string out_root_;
  core::MaterialLibrary library_;
  ::ros::ServiceServer compare_server_, diagnose_server_;
  ::ros::Publisher corrected_room_publisher_;
};

}  // namespace room_reverb::ros_bridge
