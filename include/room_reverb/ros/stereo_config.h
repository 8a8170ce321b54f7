#pragma once
// The semi-global matching settings of cfg/SphericalDepth.cfg as the core's options. One
// list of parameters for both nodes that run the stereo: spherical_depth (changed live
// with dynamic_reconfigure) and room_model (read once, for ~build requests with images).
#include <ros/ros.h>
#include <room_reverb/SphericalDepthConfig.h>

#include "room_reverb/vision/spherical_stereo.h"

namespace room_reverb::ros_bridge {

core::SphericalStereoOptions stereoOptionsFromConfig(const room_reverb::SphericalDepthConfig& config);

// The config's parameters from the private namespace (defaults from the .cfg, values
// clamped to its ranges), without a reconfigure server.
room_reverb::SphericalDepthConfig stereoConfigFromParams(const ::ros::NodeHandle& private_nh);

}  // namespace room_reverb::ros_bridge
