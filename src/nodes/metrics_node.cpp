// metrics_node: offers ~compute_metrics (room_reverb/ComputeMetrics), ISO 3382-1
// room-acoustic parameters of an impulse response. Parameters: config/metrics_node.yaml.
#include <ros/ros.h>

#include "room_reverb/ros/metrics_server.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "metrics_node");
  ros::NodeHandle private_nh("~");
  try {
    room_reverb::ros_bridge::MetricsServer server(private_nh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("metrics_node: %s", e.what());
    return 2;
  }
  return 0;
}
