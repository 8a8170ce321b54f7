// spherical_depth as a nodelet, so that images reach it without serialisation when the
// capture and stereo run in one nodelet manager (2048 x 1024 colour is 6 MB a frame).
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <memory>

#include "room_reverb/ros/spherical_depth_server.h"

namespace room_reverb::ros_bridge {

class SphericalDepthNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      server_ = std::make_unique<SphericalDepthServer>(getNodeHandle(), getPrivateNodeHandle());
    } catch (const std::exception& e) {
      NODELET_FATAL("spherical_depth: %s", e.what());
      throw;
    }
  }

  std::unique_ptr<SphericalDepthServer> server_;
};

}  // namespace room_reverb::ros_bridge

PLUGINLIB_EXPORT_CLASS(room_reverb::ros_bridge::SphericalDepthNodelet, nodelet::Nodelet)
