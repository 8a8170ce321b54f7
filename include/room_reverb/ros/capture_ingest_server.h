#pragma once
// The capture_ingest node: the rig's two camera images, as the cameras give them (dual
// fisheye or equirectangular), to the equirectangular pair the stereo takes, turned to the
// room's walls (core::ingestCapture, vision/capture_ingest.h).
//
// Input: top/image_raw and bottom/image_raw (sensor_msgs/Image, paired by time stamp), or
// the files ~top_file and ~bottom_file (published once at start, then every ~file_period_s
// if positive). With ~leveling imu or imu_and_image, the latest `imu` (sensor_msgs/Imu)
// orientation.
// Output:
//   top/image_equirect, bottom/image_equirect   bgr8 (or mono8), frame ~rig_frame
//   rig_tilt         geometry_msgs/QuaternionStamped, latched: the rig's tilt (aligned rig
//                    -> level), which room_model applies to the cloud (image_leveling.h)
//   ~image_rotation  geometry_msgs/QuaternionStamped, latched: the turn applied to the
//                    images (camera -> aligned rig, about the baseline)
// A pair that cannot be used (sizes differ, not 2:1, no Manhattan structure for image
// leveling) is logged with the reason and counted; the node keeps running.
// config/capture_ingest.yaml documents the parameters.
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "room_reverb/vision/capture_ingest.h"

namespace room_reverb::ros_bridge {

class CaptureIngestServer {
 public:
  // Throws core::InputError for a bad parameter or unreadable ~top_file / ~bottom_file.
  CaptureIngestServer(::ros::NodeHandle nh, ::ros::NodeHandle private_nh);

  std::size_t pairsPublished() const { return published_; }
  std::size_t pairsRefused() const { return refused_; }

 private:
  using Policy = message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;

  void onPair(const sensor_msgs::ImageConstPtr& top, const sensor_msgs::ImageConstPtr& bottom);
  void onImu(const sensor_msgs::ImuConstPtr& imu);
  void onFileTimer(const ::ros::WallTimerEvent&);
  // Ingests and publishes; logs and counts a refused pair.
  void process(const cv::Mat& top, const cv::Mat& bottom, const std_msgs::Header& header);

  ::ros::NodeHandle nh_;
  ::ros::NodeHandle private_nh_;
  core::CaptureIngestOptions options_;
  std::string rig_frame_;
  cv::Mat file_top_, file_bottom_;

  std::mutex imu_mutex_;
  std::optional<Eigen::Quaterniond> imu_;

  message_filters::Subscriber<sensor_msgs::Image> top_sub_;
  message_filters::Subscriber<sensor_msgs::Image> bottom_sub_;
  std::unique_ptr<message_filters::Synchronizer<Policy>> sync_;
  ::ros::Subscriber imu_sub_;
  ::ros::WallTimer file_timer_;
  ::ros::Publisher top_pub_, bottom_pub_, tilt_pub_, rotation_pub_;
  std::atomic<std::size_t> published_{0};
  std::atomic<std::size_t> refused_{0};
};

}  // namespace room_reverb::ros_bridge
