#include "room_reverb/ros/capture_ingest_server.h"

#include <geometry_msgs/QuaternionStamped.h>
#include <opencv2/imgcodecs.hpp>

#include <boost/bind/bind.hpp>
#include <cmath>

#include "room_reverb/common/error.h"
#include "room_reverb/ros/image_conversions.h"
#include "room_reverb/ros/parameters.h"
#include "room_reverb/vision/image_leveling.h"

namespace room_reverb::ros_bridge {

namespace {

geometry_msgs::QuaternionStamped quaternionMessage(const Eigen::Matrix3d& rotation, const std_msgs::Header& header) {
  const Eigen::Quaterniond q(rotation);
  geometry_msgs::QuaternionStamped msg;
  msg.header = header;
  msg.quaternion.x = q.x();
  msg.quaternion.y = q.y();
  msg.quaternion.z = q.z();
  msg.quaternion.w = q.w();
  return msg;
}

cv::Mat readCameraFile(const std::string& path, const std::string& param) {
  const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  if (image.empty()) throw core::InputError("parameter ~" + param + ": cannot read an image from '" + path + "'");
  return image;
}

}  // namespace

CaptureIngestServer::CaptureIngestServer(::ros::NodeHandle nh, ::ros::NodeHandle private_nh)
    : nh_(nh), private_nh_(private_nh) {
  std::string format, leveling, calibration, top_file, bottom_file;
  typedParam(private_nh_, "input_format", format, std::string("equirect"));
  typedParam(private_nh_, "leveling", leveling, std::string("image"));
  typedParam(private_nh_, "calibration_file", calibration, std::string(""));
  typedParam(private_nh_, "rig_frame", rig_frame_, std::string("rig"));
  typedParam(private_nh_, "top_file", top_file, std::string(""));
  typedParam(private_nh_, "bottom_file", bottom_file, std::string(""));
  options_.format = core::parseCaptureImageFormat(format, "parameter ~input_format");
  options_.leveling = core::parseLevelingSource(leveling, "parameter ~leveling");
  typedParam(private_nh_, "width", options_.width, 0);
  typedParam(private_nh_, "rectify_pair", options_.rectification.enabled, true);
  if (options_.width < 0 || options_.width % 2 != 0) {
    throw core::InputError("parameter ~width must be 0 (as the input) or an even number of pixels");
  }
  if (options_.format == core::CaptureImageFormat::kDualFisheye) {
    options_.calibration =
        core::loadDualFisheyeCalibration(calibration.empty() ? core::defaultDualFisheyeCalibrationPath() : calibration);
  }
  double file_period_s = 0.0;
  typedParam(private_nh_, "file_period_s", file_period_s, 0.0);

  top_pub_ = nh_.advertise<sensor_msgs::Image>("top/image_equirect", 1, true);
  bottom_pub_ = nh_.advertise<sensor_msgs::Image>("bottom/image_equirect", 1, true);
  tilt_pub_ = nh_.advertise<geometry_msgs::QuaternionStamped>("rig_tilt", 1, true);
  rotation_pub_ = private_nh_.advertise<geometry_msgs::QuaternionStamped>("image_rotation", 1, true);
  if (options_.leveling == core::LevelingSource::kImu || options_.leveling == core::LevelingSource::kImuAndImage) {
    imu_sub_ = nh_.subscribe("imu", 10, &CaptureIngestServer::onImu, this);
  }

  if (top_file.empty() != bottom_file.empty()) {
    throw core::InputError("parameters ~top_file and ~bottom_file: give both or neither");
  }
  if (!top_file.empty()) {
    file_top_ = readCameraFile(top_file, "top_file");
    file_bottom_ = readCameraFile(bottom_file, "bottom_file");
    // After the publishers have had a moment to connect; latched anyway.
    file_timer_ = nh_.createWallTimer(::ros::WallDuration(file_period_s > 0.0 ? file_period_s : 0.5),
                                      &CaptureIngestServer::onFileTimer, this, file_period_s <= 0.0);
    return;
  }
  const int queue = positiveIntParam(private_nh_, "queue_size", 2);
  top_sub_.subscribe(nh_, "top/image_raw", static_cast<std::uint32_t>(queue));
  bottom_sub_.subscribe(nh_, "bottom/image_raw", static_cast<std::uint32_t>(queue));
  sync_ = std::make_unique<message_filters::Synchronizer<Policy>>(Policy(static_cast<std::uint32_t>(queue) + 3), top_sub_,
                                                                  bottom_sub_);
  sync_->registerCallback(boost::bind(&CaptureIngestServer::onPair, this, boost::placeholders::_1, boost::placeholders::_2));
}

void CaptureIngestServer::onImu(const sensor_msgs::ImuConstPtr& imu) {
  const auto& q = imu->orientation;
  // REP 145: a covariance of -1 in its first element means no orientation estimate.
  if (imu->orientation_covariance[0] < 0.0) return;
  const Eigen::Quaterniond orientation(q.w, q.x, q.y, q.z);
  try {
    // What the levelling refuses is dropped here: stored, it would replace the last good
    // orientation and fail every pair until the next good one.
    core::cameraUpFromImu(orientation);
  } catch (const core::InputError& e) {
    ROS_WARN_THROTTLE(5.0, "capture_ingest: imu ignored, the last good orientation stays: %s", e.what());
    return;
  }
  std::lock_guard<std::mutex> lock(imu_mutex_);
  imu_ = orientation;
}

void CaptureIngestServer::onFileTimer(const ::ros::WallTimerEvent&) {
  std_msgs::Header header;
  header.stamp = ::ros::Time::now();
  process(file_top_, file_bottom_, header);
}

void CaptureIngestServer::onPair(const sensor_msgs::ImageConstPtr& top, const sensor_msgs::ImageConstPtr& bottom) {
  try {
    process(cameraImageFromMessage(*top, "top/image_raw"), cameraImageFromMessage(*bottom, "bottom/image_raw"),
            top->header);
  } catch (const core::InputError& e) {
    ++refused_;
    ROS_ERROR("capture_ingest: pair refused: %s", e.what());
  }
}

void CaptureIngestServer::process(const cv::Mat& top, const cv::Mat& bottom, const std_msgs::Header& in_header) {
  std::optional<Eigen::Quaterniond> imu;
  {
    std::lock_guard<std::mutex> lock(imu_mutex_);
    imu = imu_;
  }
  try {
    const core::IngestedCapture capture = core::ingestCapture(top, bottom, options_, imu);
    std_msgs::Header header = in_header;
    header.frame_id = rig_frame_;
    const std::string encoding = capture.top.channels() == 1 ? "mono8" : "bgr8";
    tilt_pub_.publish(quaternionMessage(capture.leveling.tilt, header));
    rotation_pub_.publish(quaternionMessage(capture.leveling.image_rotation, header));
    top_pub_.publish(imageToMessage(capture.top, encoding, header));
    bottom_pub_.publish(imageToMessage(capture.bottom, encoding, header));
    ++published_;
    for (const std::string& warning : capture.warnings) ROS_WARN("capture_ingest: %s", warning.c_str());
    ROS_INFO("capture_ingest: %dx%d pair, turned %.2f deg about the baseline, rig tilt %.2f deg", capture.top.cols,
             capture.top.rows, capture.leveling.yaw_rad * 180.0 / M_PI, capture.leveling.tilt_rad * 180.0 / M_PI);
  } catch (const core::InputError& e) {
    ++refused_;
    ROS_ERROR("capture_ingest: pair refused: %s", e.what());
  } catch (const cv::Exception& e) {
    ++refused_;
    ROS_ERROR("capture_ingest: pair refused: %s", e.what());
  }
}

}  // namespace room_reverb::ros_bridge
