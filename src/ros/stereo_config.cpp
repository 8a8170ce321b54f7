#include "room_reverb/ros/stereo_config.h"

namespace room_reverb::ros_bridge {

core::SphericalStereoOptions stereoOptionsFromConfig(const room_reverb::SphericalDepthConfig& config) {
  core::SphericalStereoOptions options;
  options.min_range_m = config.min_range_m;
  options.max_range_m = config.max_range_m;
  options.polar_cap_deg = config.polar_cap_deg;
  options.block_size = config.block_size;
  options.p1_per_channel = config.p1_per_channel;
  options.p2_per_channel = config.p2_per_channel;
  options.uniqueness_ratio = config.uniqueness_ratio;
  options.speckle_window_size = config.speckle_window_size;
  options.speckle_range = config.speckle_range;
  options.disp12_max_diff = config.disp12_max_diff;
  options.full_dp = config.full_dp;
  options.fill_holes = config.fill_holes;
  options.max_hole_px = config.max_hole_px;
  options.subpixel_refinement = config.subpixel_refinement;
  options.planar_refinement = config.planar_refinement;
  options.planar_max_range_m = config.planar_max_range_m;
  options.min_texture_snr = config.min_texture_snr;
  options.match_exposure = config.match_exposure;
  return options;
}

room_reverb::SphericalDepthConfig stereoConfigFromParams(const ::ros::NodeHandle& private_nh) {
  room_reverb::SphericalDepthConfig config = room_reverb::SphericalDepthConfig::__getDefault__();
  config.__fromServer__(private_nh);
  config.__clamp__();
  return config;
}

}  // namespace room_reverb::ros_bridge
