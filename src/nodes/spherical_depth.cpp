// spherical_depth: a vertical stereo pair of equirectangular images to a range image and a
// point cloud (ros/spherical_depth_server.h). Also available as the nodelet
// room_reverb/SphericalDepthNodelet. Parameters: config/spherical_depth.yaml.
#include <ros/ros.h>

#include "room_reverb/common/memory_reuse.h"
#include "room_reverb/ros/spherical_depth_server.h"

int main(int argc, char** argv) {
  room_reverb::core::keepFreedMemoryForReuse();
  ros::init(argc, argv, "spherical_depth");
  try {
    room_reverb::ros_bridge::SphericalDepthServer server{ros::NodeHandle(), ros::NodeHandle("~")};
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("spherical_depth: %s", e.what());
    return 2;
  }
  return 0;
}
