// capture_ingest: the rig's two camera images (dual fisheye or equirectangular, from
// topics or files) to the levelled equirectangular pair the stereo takes
// (ros/capture_ingest_server.h). Parameters: config/capture_ingest.yaml.
#include <ros/ros.h>

#include "room_reverb/ros/capture_ingest_server.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "capture_ingest");
  try {
    room_reverb::ros_bridge::CaptureIngestServer server{ros::NodeHandle(), ros::NodeHandle("~")};
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("capture_ingest: %s", e.what());
    return 2;
  }
  return 0;
}
