// evaluation: measured against simulated. Offers ~compare
// (room_reverb/CompareMeasurement) and ~diagnose (room_reverb/DiagnoseRoom), and
// publishes the room a diagnosis corrected on ~corrected_room (latched).
// Parameters: config/evaluation.yaml.
#include <ros/ros.h>

#include "room_reverb/common/memory_reuse.h"
#include "room_reverb/ros/evaluation_server.h"

int main(int argc, char** argv) {
  room_reverb::core::keepFreedMemoryForReuse();
  ros::init(argc, argv, "evaluation");
  ros::NodeHandle private_nh("~");
  try {
    room_reverb::ros_bridge::EvaluationServer server(private_nh);
    // A diagnosis takes a minute or two: a second thread keeps ~compare answering meanwhile.
    ros::AsyncSpinner spinner(2);
    spinner.start();
    ros::waitForShutdown();
  } catch (const std::exception& e) {
    ROS_FATAL("evaluation: %s", e.what());
    return 2;
  }
  return 0;
}
