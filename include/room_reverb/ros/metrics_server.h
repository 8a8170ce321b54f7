#pragma once
// The ComputeMetrics service over the core's metrics.
#include <ros/ros.h>
#include <room_reverb/ComputeMetrics.h>

namespace room_reverb::ros_bridge {

// Answers ~compute_metrics. Never throws across ROS: bad input gives success=false and a
// message saying what was wrong.
class MetricsServer {
 public:
  explicit MetricsServer(::ros::NodeHandle& private_nh);

  // The service body, callable without ROS for tests.
  bool compute(room_reverb::ComputeMetrics::Request& request,
               room_reverb::ComputeMetrics::Response& response);

 private:
  std::string default_bands_;
  ::ros::ServiceServer server_;
};

}  // namespace room_reverb::ros_bridge
