// rsao_estimator: offers ~estimate (room_reverb/EstimateRsao), the reverberant spatial audio
// object of a B-format RIR, also for RIRs arriving on ~impulse_response; publishes the last
// estimate latched on ~rsao and as rviz markers on ~markers. Parameters:
// config/rsao_estimator.yaml.
#include <ros/ros.h>

#include "room_reverb/ros/rsao_estimator_server.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "rsao_estimator");
  ros::NodeHandle private_nh("~");
  try {
    room_reverb::ros_bridge::RsaoEstimatorServer server(private_nh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("rsao_estimator: %s", e.what());
    return 2;
  }
  return 0;
}
