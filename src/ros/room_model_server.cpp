#include "room_reverb/ros/room_model_server.h"

#include <geometry_msgs/TransformStamped.h>
#include <room_reverb/RoomModel.h>
#include <visualization_msgs/MarkerArray.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "room_reverb/common/error.h"
#include "room_reverb/ros/cloud_conversions.h"
#include "room_reverb/ros/image_conversions.h"
#include "room_reverb/ros/parameters.h"
#include "room_reverb/ros/room_conversions.h"
#include "room_reverb/ros/room_markers.h"
#include "room_reverb/ros/stereo_config.h"

namespace room_reverb::ros_bridge {

namespace {

geometry_msgs::TransformStamped roomToRig(const core::RoomLayout& layout, const std::string& room,
                                          const std::string& rig, const ::ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = room;
  t.child_frame_id = rig;
  const Eigen::Vector3d p = layout.room_from_rig.translation();
  const Eigen::Quaterniond q(layout.room_from_rig.rotation());
  t.transform.translation.x = p.x();
  t.transform.translation.y = p.y();
  t.transform.translation.z = p.z();
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  return t;
}

void readLayoutParams(const ::ros::NodeHandle& nh, core::RoomLayoutOptions& o) {
  typedParam(nh, "voxel_size_m", o.voxel_size_m, o.voxel_size_m);
  // Not max_range_m: the stereo's parameter of that name (config/spherical_depth.yaml) is
  // read from the same namespace for ~build requests that carry images.
  typedParam(nh, "layout_max_range_m", o.max_range_m, o.max_range_m);
  typedParam(nh, "range_noise_fraction", o.range_noise_fraction, o.range_noise_fraction);
  typedParam(nh, "min_object_extent_m", o.min_object_extent_m, o.min_object_extent_m);
  int min_points = static_cast<int>(o.min_points);
  typedParam(nh, "min_points", min_points, min_points);
  if (min_points < 1) throw core::InputError("parameter ~min_points must be at least 1");
  o.min_points = static_cast<std::size_t>(min_points);
}

}  // namespace

RoomModelServer::RoomModelServer(::ros::NodeHandle nh, ::ros::NodeHandle private_nh) : nh_(nh), private_nh_(private_nh) {
  baseline_m_ = positiveDoubleParam(private_nh_, "baseline_m", 0.2);
  typedParam(private_nh_, "rig_frame", rig_frame_, std::string("rig"));
  typedParam(private_nh_, "room_frame", room_frame_, std::string("room"));
  typedParam(private_nh_, "output_file", output_file_, std::string(""));
  typedParam(private_nh_, "cloud_file", cloud_file_, std::string(""));
  typedParam(private_nh_, "build_on_cloud", build_on_cloud_, false);
  typedParam(private_nh_, "level_from_cloud", options_.level_from_cloud, false);
  typedParam(private_nh_, "surface_relief", options_.relief.enabled, true);
  typedParam(private_nh_, "disparity_offset_correction", options_.disparity_offset.enabled, true);
  options_.stereo = stereoOptionsFromConfig(stereoConfigFromParams(private_nh_));
  readLayoutParams(private_nh_, options_.layout);
  std::string classifier_file, families_file;
  typedParam(private_nh_, "material_classifier_file", classifier_file, std::string(""));
  typedParam(private_nh_, "material_families_file", families_file, std::string(""));
  // A path, read on every build (the user may correct it between builds).
  typedParam(private_nh_, "materials_override", options_.materials.override_file, std::string(""));
  options_.classifier = std::make_shared<const core::MaterialClassifier>(core::MaterialClassifier::load(
      classifier_file.empty() ? core::MaterialClassifier::defaultPath() : classifier_file));
  options_.families = std::make_shared<const core::MaterialFamilyTable>(core::loadMaterialFamilyTable(
      families_file.empty() ? core::defaultMaterialFamilyTablePath() : families_file, core::MaterialLibrary::loadDefault()));

  room_pub_ = private_nh_.advertise<room_reverb::RoomModel>("room", 1, true);
  marker_pub_ = private_nh_.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
  // The image and the tilt before the cloud: the three are latched, and a room_model that
  // starts after a capture should hold the capture's image and tilt when its cloud comes.
  image_sub_ = nh_.subscribe("top/image_equirect", 1, &RoomModelServer::onImage, this);
  tilt_sub_ = nh_.subscribe("rig_tilt", 1, &RoomModelServer::onTilt, this);
  cloud_sub_ = nh_.subscribe("points", 1, &RoomModelServer::onCloud, this);
  service_ = private_nh_.advertiseService("build", &RoomModelServer::build, this);
}

void RoomModelServer::onImage(const sensor_msgs::ImageConstPtr& image) {
  try {
    // Refused now, not at the next build: the last good image stays.
    checkCameraImageMessage(*image, "top/image_equirect");
  } catch (const core::InputError& e) {
    ROS_WARN("room_model: %s; ignored, the last good image stays", e.what());
    return;
  }
  bool build = false;
  {
    std::lock_guard<std::mutex> lock(latest_mutex_);
    latest_image_ = image;
    build = build_waits_for_image_;
    build_waits_for_image_ = false;
  }
  if (build) buildOnCloud();
}

void RoomModelServer::onTilt(const geometry_msgs::QuaternionStampedConstPtr& tilt) {
  const auto& q = tilt->quaternion;
  const Eigen::Quaterniond rotation(q.w, q.x, q.y, q.z);
  if (!rotation.coeffs().allFinite() || std::abs(rotation.norm() - 1.0) > 1e-3) {
    ROS_WARN("room_model: ignoring a rig_tilt that is not a unit quaternion");
    return;
  }
  std::lock_guard<std::mutex> lock(latest_mutex_);
  tilt_ = rotation.normalized().toRotationMatrix();
}

void RoomModelServer::onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud) {
  try {
    // Refused now, not at the next build: the last good cloud stays.
    checkCloudMessage(*cloud);
  } catch (const core::InputError& e) {
    ROS_WARN("room_model: %s; ignored, the last good cloud stays", e.what());
    return;
  }
  bool waits = false;
  {
    std::lock_guard<std::mutex> lock(latest_mutex_);
    latest_cloud_ = cloud;
    // Latched topics reach a node that starts after a capture in any order.
    waits = build_waits_for_image_ = build_on_cloud_ && !latest_image_;
  }
  if (waits) {
    ROS_INFO("room_model: a cloud and no image yet; the build waits for %s",
             nh_.resolveName("top/image_equirect").c_str());
  } else if (build_on_cloud_) {
    buildOnCloud();
  }
}

void RoomModelServer::buildOnCloud() {
  room_reverb::BuildRoomModel::Request request;
  room_reverb::BuildRoomModel::Response response;
  build(request, response);
  if (!response.success) ROS_WARN("room_model: build on the new cloud failed: %s", response.message.c_str());
}

bool RoomModelServer::build(room_reverb::BuildRoomModel::Request& request,
                            room_reverb::BuildRoomModel::Response& response) {
  std::lock_guard<std::mutex> build_lock(build_mutex_);
  const auto start = std::chrono::steady_clock::now();
  response.success = false;
  try {
    const double baseline = request.baseline_m != 0.0 ? request.baseline_m : baseline_m_;
    const bool has_top = request.top.width > 0 || !request.top.data.empty();
    const bool has_bottom = request.bottom.width > 0 || !request.bottom.data.empty();
    const bool has_range = request.range.width > 0 || !request.range.data.empty();
    if (has_bottom && has_range) throw core::InputError("give the bottom image or the range image, not both");
    if (has_top != (has_bottom || has_range)) {
      throw core::InputError("give the top image with the bottom image or a range image, or no image at all");
    }
    if (has_range) {
      const cv::Mat top = cameraImageFromMessage(request.top, "request top image");
      const core::SphericalDepth depth =
          core::depthFromRangeImage(rangeImageFromMessage(request.range, "request range image"), top.size(), "request range image");
      const core::PointCloud cloud = core::depthToPointCloud(depth, top, baseline, options_.cloud);
      buildFrom(&cloud, top, nullptr, baseline, Eigen::Matrix3d::Identity(), request.top.header, response);
    } else if (has_top) {
      const cv::Mat top = cameraImageFromMessage(request.top, "request top image");
      const cv::Mat bottom = cameraImageFromMessage(request.bottom, "request bottom image");
      buildFrom(nullptr, top, &bottom, baseline, Eigen::Matrix3d::Identity(), request.top.header, response);
    } else {
      sensor_msgs::PointCloud2ConstPtr cloud_msg;
      sensor_msgs::ImageConstPtr image_msg;
      Eigen::Matrix3d tilt;
      {
        std::lock_guard<std::mutex> lock(latest_mutex_);
        cloud_msg = latest_cloud_;
        image_msg = latest_image_;
        tilt = tilt_;
      }
      if (!cloud_msg) {
        throw core::InputError("no point cloud received yet on " + nh_.resolveName("points") +
                               " (or give top and bottom images in the request)");
      }
      if (!image_msg) throw core::InputError("no image received yet on " + nh_.resolveName("top/image_equirect"));
      // With ~build_on_cloud the latest cloud was usually built on arrival: answer with that
      // room instead of fitting the same cloud again.
      if (last_built_.cloud == cloud_msg && last_built_.image == image_msg && last_built_.tilt == tilt &&
          last_built_.baseline_m == baseline) {
        response = last_built_.response;
        response.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return true;
      }
      const core::PointCloud cloud = cloudFromMessage(*cloud_msg);
      if (!cloud.frame.empty() && cloud.frame != rig_frame_) {
        throw core::InputError("the cloud is in frame '" + cloud.frame + "', expected the rig frame '" + rig_frame_ + "'");
      }
      const cv::Mat top = cameraImageFromMessage(*image_msg, "top/image_equirect");
      buildFrom(&cloud, top, nullptr, baseline, tilt, cloud_msg->header, response);
      response.success = true;
      last_built_ = {cloud_msg, image_msg, tilt, baseline, response};
    }
    response.success = true;
  } catch (const core::InputError& e) {
    response.message = e.what();
  } catch (const cv::Exception& e) {
    response.message = std::string("OpenCV: ") + e.what();
  }
  response.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!response.success) ROS_WARN("room_model: ~build failed: %s", response.message.c_str());
  return true;
}

void RoomModelServer::buildFrom(const core::PointCloud* cloud, const cv::Mat& top, const cv::Mat* bottom,
                                double baseline_m, const Eigen::Matrix3d& tilt, const std_msgs::Header& header,
                                room_reverb::BuildRoomModel::Response& response) {
  core::RoomLayout layout;
  if (cloud != nullptr) {
    layout = core::roomLayoutFromCloud(*cloud, top, baseline_m, options_, tilt);
    response.cloud_points = static_cast<std::uint32_t>(cloud->points.size());
    if (!cloud_file_.empty()) core::savePointCloudPcd(cloud_file_, *cloud);
  } else {
    core::VisualRoute route = core::runVisualRoute(top, *bottom, baseline_m, options_);
    response.cloud_points = static_cast<std::uint32_t>(route.cloud.points.size());
    if (!cloud_file_.empty()) core::savePointCloudPcd(cloud_file_, route.cloud);
    layout = std::move(route.layout);
  }
  if (!output_file_.empty()) core::saveRoomModel(output_file_, layout.model);
  publish(layout, header.stamp.isZero() ? ::ros::Time::now() : header.stamp, response);
}

void RoomModelServer::publish(const core::RoomLayout& layout, const ::ros::Time& stamp,
                              room_reverb::BuildRoomModel::Response& response) {
  response.room = toMessage(layout.model);
  response.room.header.stamp = stamp;
  response.room.header.frame_id = room_frame_;
  response.room_to_rig = roomToRig(layout, room_frame_, rig_frame_, stamp);
  room_pub_.publish(response.room);
  marker_pub_.publish(roomMarkers(layout.model, room_frame_, stamp));
  tf_broadcaster_.sendTransform(response.room_to_rig);
  const Eigen::Vector3d& s = layout.model.size_m;
  char summary[200];
  std::snprintf(summary, sizeof(summary), "room %.2f x %.2f x %.2f m%s, %zu objects, rig yaw %.1f deg", s.x(), s.y(),
                s.z(), layout.model.has_ceiling ? "" : " (no ceiling)", layout.model.objects.size(),
                layout.rig_yaw_rad * 180.0 / M_PI);
  response.message = summary;
  ROS_INFO("room_model: %s", summary);
  for (const std::string& warning : layout.warnings) {
    response.message += "; " + warning;
    ROS_WARN("room_model: %s", warning.c_str());
  }
}

}  // namespace room_reverb::ros_bridge
