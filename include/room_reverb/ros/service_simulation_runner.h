#pragma once
// Simulations handed to room_simulator nodes (their ~simulate_job service), anywhere on
// the ROS graph: one slot per service, each running one job at a time (simulation_runner.h).
// ROS's multi-machine launch places the nodes (launch/distributed_evaluation.launch).
#include <ros/ros.h>

#include <string>
#include <vector>

#include "room_reverb/acoustics/simulation_runner.h"

namespace room_reverb::ros_bridge {

class ServiceSimulationRunner : public core::RemoteSimulationRunner {
 public:
  // Waits up to `wait_s` for every service to be offered; InputError naming those that are
  // not (the node is not running, or the name lacks its namespace).
  ServiceSimulationRunner(std::vector<std::string> services, double wait_s);
  std::string description() const override;

 protected:
  std::size_t slots() const override { return services_.size(); }
  Reply runOn(std::size_t slot, const std::vector<std::uint8_t>& job) override;

 private:
  std::vector<std::string> services_;
  std::vector<::ros::ServiceClient> clients_;  // persistent; client k is used by slot k only
};

}  // namespace room_reverb::ros_bridge
