#include "room_reverb/ros/spherical_depth_server.h"

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/image_encodings.h>

#include <boost/bind/bind.hpp>
#include <chrono>
#include <vector>

#include "room_reverb/common/error.h"
#include "room_reverb/ros/cloud_conversions.h"
#include "room_reverb/ros/image_conversions.h"
#include "room_reverb/ros/parameters.h"
#include "room_reverb/ros/stereo_config.h"

namespace room_reverb::ros_bridge {

namespace {

geometry_msgs::TransformStamped cameraTransform(const std::string& rig, const std::string& camera, double z) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = ::ros::Time::now();
  t.header.frame_id = rig;
  t.child_frame_id = camera;
  t.transform.translation.z = z;
  t.transform.rotation.w = 1.0;
  return t;
}

}  // namespace

SphericalDepthServer::SphericalDepthServer(::ros::NodeHandle nh, ::ros::NodeHandle private_nh)
    : nh_(nh), private_nh_(private_nh) {
  baseline_m_ = positiveDoubleParam(private_nh_, "baseline_m", 0.2);
  typedParam(private_nh_, "rig_frame", rig_frame_, std::string("rig"));
  typedParam(private_nh_, "top_camera_frame", top_frame_, std::string("rig_top_camera"));
  typedParam(private_nh_, "bottom_camera_frame", bottom_frame_, std::string("rig_bottom_camera"));
  cloud_options_.stride = positiveIntParam(private_nh_, "cloud_stride", 1);
  typedParam(private_nh_, "include_filled", cloud_options_.include_filled, false);
  const int queue = positiveIntParam(private_nh_, "queue_size", 2);

  stereo_options_ = stereoOptionsFromConfig(stereoConfigFromParams(private_nh_));
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<room_reverb::SphericalDepthConfig>>(reconfigure_mutex_,
                                                                                                   private_nh_);
  reconfigure_->setCallback([this](room_reverb::SphericalDepthConfig& config, std::uint32_t level) {
    onReconfigure(config, level);
  });

  // Latched, as capture_ingest's images: a room_model that starts (or respawns) after the
  // capture builds from the last cloud instead of waiting for the next capture.
  range_pub_ = nh_.advertise<sensor_msgs::Image>("range_image", 1, true);
  cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("points", 1, true);
  publishCameraTransforms();

  top_sub_.subscribe(nh_, "top/image_equirect", static_cast<std::uint32_t>(queue));
  bottom_sub_.subscribe(nh_, "bottom/image_equirect", static_cast<std::uint32_t>(queue));
  sync_ = std::make_unique<message_filters::Synchronizer<Policy>>(Policy(static_cast<std::uint32_t>(queue) + 3), top_sub_,
                                                                  bottom_sub_);
  sync_->registerCallback(boost::bind(&SphericalDepthServer::onPair, this, boost::placeholders::_1, boost::placeholders::_2));
}

void SphericalDepthServer::onReconfigure(const room_reverb::SphericalDepthConfig& config, std::uint32_t) {
  core::SphericalStereoOptions options = stereoOptionsFromConfig(config);
  if (options.p2_per_channel <= options.p1_per_channel) {
    ROS_WARN("spherical_depth: p2_per_channel (%d) must exceed p1_per_channel (%d); keeping P2 = P1 + 1",
             options.p2_per_channel, options.p1_per_channel);
    options.p2_per_channel = options.p1_per_channel + 1;
  }
  if (options.block_size % 2 == 0) options.block_size += 1;  // the matcher needs an odd block
  std::lock_guard<std::mutex> lock(options_mutex_);
  stereo_options_ = options;
}

void SphericalDepthServer::publishCameraTransforms() {
  std::vector<geometry_msgs::TransformStamped> transforms{cameraTransform(rig_frame_, top_frame_, 0.5 * baseline_m_),
                                                          cameraTransform(rig_frame_, bottom_frame_, -0.5 * baseline_m_)};
  tf_broadcaster_.sendTransform(transforms);
}

void SphericalDepthServer::onPair(const sensor_msgs::ImageConstPtr& top, const sensor_msgs::ImageConstPtr& bottom) {
  core::SphericalStereoOptions options;
  {
    std::lock_guard<std::mutex> lock(options_mutex_);
    options = stereo_options_;
  }
  try {
    const auto start = std::chrono::steady_clock::now();
    const cv::Mat top_image = cameraImageFromMessage(*top, "top/image_equirect");
    const cv::Mat bottom_image = cameraImageFromMessage(*bottom, "bottom/image_equirect");
    const core::SphericalDepth depth = core::computeSphericalDepth(top_image, bottom_image, baseline_m_, options);
    const core::PointCloud cloud = core::depthToPointCloud(depth, top_image, baseline_m_, cloud_options_);

    std_msgs::Header range_header = top->header;
    range_header.frame_id = top_frame_;
    range_pub_.publish(imageToMessage(depth.range_m, sensor_msgs::image_encodings::TYPE_32FC1, range_header));
    std_msgs::Header cloud_header = top->header;
    cloud_header.frame_id = rig_frame_;
    cloud_pub_.publish(cloudToMessage(cloud, cloud_header));
    ++processed_;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ROS_DEBUG("spherical_depth: %ux%u pair -> %zu points in %.2f s", top->width, top->height, cloud.points.size(), seconds);
  } catch (const core::InputError& e) {
    ++refused_;
    ROS_ERROR("spherical_depth: pair refused: %s", e.what());
  } catch (const cv::Exception& e) {
    ++refused_;
    ROS_ERROR("spherical_depth: pair refused: %s", e.what());
  }
}

}  // namespace room_reverb::ros_bridge
