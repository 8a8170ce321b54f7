#pragma once
// The spherical_depth node's work, shared by the node and the nodelet: a vertical stereo
// pair of equirectangular images in, a range image and a point cloud out.
//
// Subscribes top/image_equirect and bottom/image_equirect (sensor_msgs/Image, paired by
// time stamp, approximately: two cameras are rarely triggered together), runs
// core::computeSphericalDepth and publishes, latched (a node that starts after a capture,
// room_model above all, gets the capture's cloud at once)
//   range_image  sensor_msgs/Image 32FC1, range from the top camera [m], NaN where invalid,
//                in the top camera's frame (~top_camera_frame)
//   points       sensor_msgs/PointCloud2 XYZRGBL in ~rig_frame (label: SurfaceHint, 0)
// and, once, the static transforms rig -> top and bottom camera (+-baseline/2 on z).
// The matcher's settings are dynamic_reconfigure parameters (cfg/SphericalDepth.cfg);
// config/spherical_depth.yaml documents every parameter. A pair the stereo refuses
// (different sizes, not 2:1, black, saturated) is logged with the reason and counted; the
// node keeps running.
#include <dynamic_reconfigure/server.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <ros/ros.h>
#include <room_reverb/SphericalDepthConfig.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include "room_reverb/vision/depth_cloud.h"
#include "room_reverb/vision/spherical_stereo.h"

namespace room_reverb::ros_bridge {

class SphericalDepthServer {
 public:
  // Throws core::InputError for a bad parameter (non-positive baseline, stride < 1).
  SphericalDepthServer(::ros::NodeHandle nh, ::ros::NodeHandle private_nh);

  std::size_t pairsProcessed() const { return processed_; }
  std::size_t pairsRefused() const { return refused_; }

 private:
  using Policy = message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;

  void onPair(const sensor_msgs::ImageConstPtr& top, const sensor_msgs::ImageConstPtr& bottom);
  void onReconfigure(const room_reverb::SphericalDepthConfig& config, std::uint32_t level);
  void publishCameraTransforms();

  ::ros::NodeHandle nh_;
  ::ros::NodeHandle private_nh_;
  double baseline_m_ = 0.2;
  std::string rig_frame_;
  std::string top_frame_;
  std::string bottom_frame_;
  core::DepthCloudOptions cloud_options_;

  std::mutex options_mutex_;  // the reconfigure callback and the pair callback
  core::SphericalStereoOptions stereo_options_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<room_reverb::SphericalDepthConfig>> reconfigure_;

  message_filters::Subscriber<sensor_msgs::Image> top_sub_;
  message_filters::Subscriber<sensor_msgs::Image> bottom_sub_;
  std::unique_ptr<message_filters::Synchronizer<Policy>> sync_;
  ::ros::Publisher range_pub_;
  ::ros::Publisher cloud_pub_;
  tf2_ros::StaticTransformBroadcaster tf_broadcaster_;
  std::atomic<std::size_t> processed_{0};
  std::atomic<std::size_t> refused_{0};
};

}  // namespace room_reverb::ros_bridge
