#pragma once
// The SimulateRoom and SimulateJob services over the core's simulation engine.
#include <ros/ros.h>
#include <room_reverb/SimulateJob.h>
#include <room_reverb/SimulateRoom.h>

#include <mutex>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/acoustics/simulation_runner.h"

namespace room_reverb::ros_bridge {

// Answers ~simulate, and ~simulate_job: a simulation another process hands over whole
// (simulation_runner.h), run with the job's own settings; only ~max_rays applies to it.
// Parameters are read once, at construction, and checked loudly
// (config/room_simulator.yaml documents them). Never throws across ROS: bad input gives
// success=false and a message.
class SimulationServer {
 public:
  explicit SimulationServer(::ros::NodeHandle& private_nh);

  // The service body, callable without ROS for tests.
  bool simulate(room_reverb::SimulateRoom::Request& request, room_reverb::SimulateRoom::Response& response);
  bool simulateJob(room_reverb::SimulateJob::Request& request, room_reverb::SimulateJob::Response& response);

 private:
  core::SimulationSettings defaults_;
  int max_rays_ = 0;  // a request for more rays is refused
  core::MaterialLibrary library_;
  ::ros::ServiceServer server_, job_server_;
  std::mutex job_mutex_;  // the executor keeps the last job's scene
  core::SimulationJobExecutor executor_;
};

}  // namespace room_reverb::ros_bridge
