#pragma once
// The room_model node: the room as labelled cuboids with materials, from the visual route.
//
// Keeps the latest `points` (PointCloud2 from spherical_depth, rig frame),
// `top/image_equirect` (for the materials) and `rig_tilt` (geometry_msgs/QuaternionStamped
// from capture_ingest: the rig's tilt, applied to the cloud before the fit; none: upright). ~build (room_reverb/BuildRoomModel) fits the
// room to them, or runs the whole route on a pair given in the request; with
// ~build_on_cloud it also builds on every new cloud. Each build publishes
//   ~room     room_reverb/RoomModel, latched
//   ~markers  visualization_msgs/MarkerArray, latched (ros/room_markers.h)
//   TF        room -> rig (static: the rig does not move during a capture)
// and, with ~output_file, writes the room.yaml (with ~cloud_file, the cloud as PCD). Bad input gives success=false and a
// message, never a dead node. config/room_model.yaml documents the parameters.
#include <geometry_msgs/QuaternionStamped.h>
#include <ros/ros.h>
#include <room_reverb/BuildRoomModel.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <mutex>
#include <string>

#include "room_reverb/vision/visual_route.h"

namespace room_reverb::ros_bridge {

class RoomModelServer {
 public:
  // Throws core::InputError for a bad parameter.
  RoomModelServer(::ros::NodeHandle nh, ::ros::NodeHandle private_nh);

  // The service body, callable without ROS spinning.
  bool build(room_reverb::BuildRoomModel::Request& request, room_reverb::BuildRoomModel::Response& response);

 private:
  void onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud);
  void buildOnCloud();  // builds from the latest inputs and publishes the room
  void onImage(const sensor_msgs::ImageConstPtr& image);
  void onTilt(const geometry_msgs::QuaternionStampedConstPtr& tilt);
  // Fits, publishes and fills the response; throws InputError / cv::Exception.
  // `tilt` levels the cloud (identity for a pair in the request: taken as upright).
  void buildFrom(const core::PointCloud* cloud, const cv::Mat& top, const cv::Mat* bottom, double baseline_m,
                 const Eigen::Matrix3d& tilt, const std_msgs::Header& header,
                 room_reverb::BuildRoomModel::Response& response);
  void publish(const core::RoomLayout& layout, const ::ros::Time& stamp, room_reverb::BuildRoomModel::Response& response);

  ::ros::NodeHandle nh_;
  ::ros::NodeHandle private_nh_;
  double baseline_m_ = 0.2;
  std::string rig_frame_;
  std::string room_frame_;
  std::string output_file_;
  std::string cloud_file_;
  bool build_on_cloud_ = false;
  core::VisualRouteOptions options_;

  std::mutex latest_mutex_;
  sensor_msgs::PointCloud2ConstPtr latest_cloud_;
  sensor_msgs::ImageConstPtr latest_image_;
  Eigen::Matrix3d tilt_ = Eigen::Matrix3d::Identity();
  // With ~build_on_cloud, a cloud came before any image: built when the image comes.
  bool build_waits_for_image_ = false;
  std::mutex build_mutex_;  // one build at a time; guards last_built_
  // The last build from the subscribed inputs, and what it was built from.
  struct LastBuild {
    sensor_msgs::PointCloud2ConstPtr cloud;
    sensor_msgs::ImageConstPtr image;
    Eigen::Matrix3d tilt = Eigen::Matrix3d::Identity();
    double baseline_m = 0.0;
    room_reverb::BuildRoomModel::Response response;
  };
  LastBuild last_built_;

  ::ros::Subscriber cloud_sub_;
  ::ros::Subscriber image_sub_;
  ::ros::Subscriber tilt_sub_;
  ::ros::ServiceServer service_;
  ::ros::Publisher room_pub_;
  ::ros::Publisher marker_pub_;
  tf2_ros::StaticTransformBroadcaster tf_broadcaster_;
};

}  // namespace room_reverb::ros_bridge
