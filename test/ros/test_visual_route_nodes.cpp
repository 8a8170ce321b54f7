// rostest: a generated stereo capture through spherical_depth (node and nodelet) and
// room_model. The cloud must arrive in the rig frame with the range image, and ~build must
// return the rendered room within the tolerances (dimensions within 3 cm or 1 %,
// yaw within 1 degree), both from the published cloud and from images in the request. Bad
// input (one image, mismatched sizes, a black pair, no cloud yet) gives success=false with a
// message, and the nodes keep working. A ~materials_override file is applied, a missing one
// refused. The whole chain from a tilted rig's dual-fisheye images (capture_ingest ->
// spherical_depth -> room_model) must find the tilt and the room.
#include <geometry_msgs/QuaternionStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <room_reverb/BuildRoomModel.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <string>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/ros/image_conversions.h"
#include "room_reverb/ros/room_conversions.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/texture_family.h"

namespace {

using namespace room_reverb;

constexpr double kPi = 3.14159265358979323846;
constexpr int kWidth = 1024;

struct Capture {
  core::CaptureScene scene;
  core::StereoCapture images;
};

const Capture& meetingRoom() {
  static const Capture capture = [] {
    Capture c;
    c.scene = core::loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/mr.yaml");
    c.scene.options.width = kWidth;
    c.images = core::renderCapture(c.scene.room, core::MaterialLibrary::loadDefault(), c.scene.options);
    return c;
  }();
  return capture;
}

sensor_msgs::Image toMessage(const cv::Mat& image, const ros::Time& stamp) {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = "rig";
  return ros_bridge::imageToMessage(image, image.channels() == 1 ? "mono8" : "bgr8", header);
}

template <typename T>
struct Latest {
  void on(const boost::shared_ptr<const T>& m) {
    std::lock_guard<std::mutex> lock(mutex);
    msg = m;
    ++count;
  }
  boost::shared_ptr<const T> get() {
    std::lock_guard<std::mutex> lock(mutex);
    return msg;
  }
  std::mutex mutex;
  boost::shared_ptr<const T> msg;
  int count = 0;
};

// Publishes the pair on ns's image topics until `points` arrives (publishers need a
// moment to connect); returns the cloud.
sensor_msgs::PointCloud2ConstPtr publishUntilCloud(ros::NodeHandle& nh, const std::string& ns, const cv::Mat& top,
                                                   const cv::Mat& bottom, double timeout_s,
                                                   Latest<sensor_msgs::Image>* range = nullptr) {
  auto top_pub = nh.advertise<sensor_msgs::Image>(ns + "/top/image_equirect", 1);
  auto bottom_pub = nh.advertise<sensor_msgs::Image>(ns + "/bottom/image_equirect", 1);
  Latest<sensor_msgs::PointCloud2> cloud;
  auto cloud_sub = nh.subscribe(ns + "/points", 1, &Latest<sensor_msgs::PointCloud2>::on, &cloud);
  ros::Subscriber range_sub;
  if (range != nullptr) range_sub = nh.subscribe(ns + "/range_image", 1, &Latest<sensor_msgs::Image>::on, range);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  ros::WallTime next_publish = ros::WallTime::now();
  while (ros::WallTime::now() < deadline && !cloud.get()) {
    if (ros::WallTime::now() >= next_publish && top_pub.getNumSubscribers() > 0 && bottom_pub.getNumSubscribers() > 0) {
      const ros::Time stamp = ros::Time::now();
      top_pub.publish(toMessage(top, stamp));
      bottom_pub.publish(toMessage(bottom, stamp));
      next_publish = ros::WallTime::now() + ros::WallDuration(3.0);
    }
    ros::WallDuration(0.05).sleep();
  }
  return cloud.get();
}

void expectMeetingRoom(const room_reverb::BuildRoomModel::Response& response, const std::string& how) {
  ASSERT_TRUE(response.success) << how << ": " << response.message;
  const core::RoomModel& truth = meetingRoom().scene.room;
  const double got[3] = {response.room.size.x, response.room.size.y, response.room.size.z};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(got[k], truth.size_m[k], std::max(0.03, 0.01 * truth.size_m[k])) << how << " axis " << k;
  }
  EXPECT_EQ(response.room.header.frame_id, "room");
  EXPECT_EQ(response.room_to_rig.header.frame_id, "room");
  EXPECT_EQ(response.room_to_rig.child_frame_id, "rig");
  const auto& q = response.room_to_rig.transform.rotation;
  const double yaw = 2.0 * std::atan2(q.z, q.w);
  const double true_yaw = 2.0 * std::atan2(truth.rig_rotation.z(), truth.rig_rotation.w());
  EXPECT_NEAR(yaw, true_yaw, kPi / 180.0) << how;
  const auto& t = response.room_to_rig.transform.translation;
  EXPECT_NEAR(std::hypot(t.x - truth.rig_position_m.x(), t.y - truth.rig_position_m.y(), t.z - truth.rig_position_m.z()),
              0.0, 0.05)
      << how;
  EXPECT_GT(response.cloud_points, 100000u) << how;
  // Materials: every face's look (texture family) as rendered; two materials of one family
  // look alike, so the family is what a camera can tell.
  const std::pair<std::string, std::string> faces[] = {
      {"floor", response.room.floor_material},         {"ceiling", response.room.ceiling_material},
      {"wall_x_min", response.room.wall_x_min_material}, {"wall_x_max", response.room.wall_x_max_material},
      {"wall_y_min", response.room.wall_y_min_material}, {"wall_y_max", response.room.wall_y_max_material}};
  for (const auto& [face, material] : faces) {
    ASSERT_FALSE(material.empty()) << how << " " << face;
    EXPECT_EQ(core::textureFamilyFor(material).family, core::textureFamilyFor(truth.surfaces.at(face).material).family)
        << how << " " << face << ": " << material << " for " << truth.surfaces.at(face).material;
  }
  ASSERT_EQ(response.room.surface_confidence.size(), 6u);
  for (const double c : response.room.surface_confidence) EXPECT_GT(c, 0.3) << how;
  for (const auto& object : response.room.objects) EXPECT_FALSE(object.material.empty()) << how << " " << object.label;
  // Each face's relief, where the route gave one: 6 x 9 coefficients; each object's, 9.
  if (!response.room.surface_relief_scattering.empty()) ASSERT_EQ(response.room.surface_relief_scattering.size(), 54u) << how;
  for (const double s : response.room.surface_relief_scattering) EXPECT_TRUE(s >= 0.0 && s <= 1.0) << how;
  for (const auto& object : response.room.objects) {
    if (!object.relief_scattering.empty()) EXPECT_EQ(object.relief_scattering.size(), 9u) << how << " " << object.label;
  }
  const core::RoomModel read = ros_bridge::fromMessage(response.room);  // what a simulator node reads of it
  for (std::size_t f = 0; f < 6 && !response.room.surface_relief_scattering.empty(); ++f) {
    const auto it = read.surfaces.find(core::kRoomSurfaceNames[f]);
    if (it == read.surfaces.end()) continue;
    EXPECT_EQ(it->second.relief_scattering[4], response.room.surface_relief_scattering[9 * f + 4]) << how;
  }
  ::testing::Test::RecordProperty(how + "_seconds", std::to_string(response.seconds));
  ::testing::Test::RecordProperty(how + "_message", response.message);
}

// `wait_for_cloud`: ask again (up to 30 s) while room_model says it has no cloud yet; a
// large cloud may reach it a little after it reached the test node.
bool callBuild(room_reverb::BuildRoomModel& srv, const std::string& service = "/room_model/build",
               bool wait_for_cloud = false) {
  if (!ros::service::waitForService(service, ros::Duration(30.0))) return false;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (true) {
    if (!ros::service::call(service, srv)) return false;
    if (!wait_for_cloud || srv.response.success || srv.response.message.find("no point cloud") == std::string::npos ||
        ros::WallTime::now() > deadline) {
      return true;
    }
    ros::WallDuration(0.5).sleep();
  }
}

// The meeting room seen from a rig turned by 20 degrees and tilted by 3 degrees, as the
// dual-fisheye images of cameras with the calibration capture_ingest is given. At 2048 x
// 1024: through fisheye stitching at 1024 x 512 the far walls come out 5-7 cm short (the
// stitched image is softer), beyond the 3 cm / 1 % tolerance.
const Capture& tiltedMeetingRoom() {
  static const Capture capture = [] {
    Capture c;
    c.scene = core::loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/mr.yaml");
    c.scene.options.width = 2 * kWidth;
    c.scene.options.fisheye = true;
    c.scene.options.fisheye_calibration =
        core::loadDualFisheyeCalibration(core::defaultDualFisheyeCalibrationPath());
    c.scene.room.rig_rotation = Eigen::AngleAxisd(20.0 * kPi / 180.0, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(3.0 * kPi / 180.0, Eigen::Vector3d(1.0, 1.0, 0.0).normalized());
    c.images = core::renderCapture(c.scene.room, core::MaterialLibrary::loadDefault(), c.scene.options);
    return c;
  }();
  return capture;
}

Eigen::Quaterniond toEigen(const geometry_msgs::Quaternion& q) { return Eigen::Quaterniond(q.w, q.x, q.y, q.z); }

TEST(VisualRouteNodes, BuildBeforeAnyCloudSaysWhatIsMissing) {
  room_reverb::BuildRoomModel srv;
  ASSERT_TRUE(callBuild(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("no point cloud"), std::string::npos) << srv.response.message;
}

TEST(VisualRouteNodes, PairToCloudToRoomModel) {
  ros::NodeHandle nh;
  const Capture& c = meetingRoom();
  Latest<sensor_msgs::Image> range;
  Latest<visualization_msgs::MarkerArray> markers;
  auto marker_sub = nh.subscribe("/room_model/markers", 1, &Latest<visualization_msgs::MarkerArray>::on, &markers);
  const auto cloud = publishUntilCloud(nh, "", c.images.top.color, c.images.bottom.color, 60.0, &range);
  ASSERT_TRUE(cloud) << "no cloud from spherical_depth";
  EXPECT_EQ(cloud->header.frame_id, "rig");
  EXPECT_GT(static_cast<double>(cloud->width) * cloud->height, 0.8 * kWidth * kWidth / 2 * 0.8);
  bool has_label = false;
  for (const auto& f : cloud->fields) has_label = has_label || f.name == "label";
  EXPECT_TRUE(has_label);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(5.0);
  while (!range.get() && ros::WallTime::now() < deadline) ros::WallDuration(0.05).sleep();
  ASSERT_TRUE(range.get());
  EXPECT_EQ(range.get()->encoding, sensor_msgs::image_encodings::TYPE_32FC1);
  EXPECT_EQ(range.get()->width, static_cast<unsigned>(kWidth));
  EXPECT_EQ(range.get()->header.frame_id, "rig_top_camera");

  // room_model has had the same cloud and image.
  room_reverb::BuildRoomModel srv;
  ASSERT_TRUE(callBuild(srv, "/room_model/build", true));
  expectMeetingRoom(srv.response, "from_cloud");
  const ros::WallTime marker_deadline = ros::WallTime::now() + ros::WallDuration(5.0);
  while (!markers.get() && ros::WallTime::now() < marker_deadline) ros::WallDuration(0.05).sleep();
  ASSERT_TRUE(markers.get());
  EXPECT_GE(markers.get()->markers.size(), 1u + 6u + 6u);  // clear, six faces, six labels
}

// A ~build request carrying the capture's pair and baseline.
room_reverb::BuildRoomModel pairRequest(const Capture& c) {
  room_reverb::BuildRoomModel srv;
  srv.request.top = toMessage(c.images.top.color, ros::Time::now());
  srv.request.bottom = toMessage(c.images.bottom.color, ros::Time::now());
  srv.request.baseline_m = c.scene.options.baseline_m;
  return srv;
}

TEST(VisualRouteNodes, PairInTheRequest) {
  const Capture& c = meetingRoom();
  room_reverb::BuildRoomModel srv = pairRequest(c);
  ASSERT_TRUE(callBuild(srv));
  expectMeetingRoom(srv.response, "from_request");
}

// Depth from elsewhere (here the generator's exact range) with the top image: no stereo.
TEST(VisualRouteNodes, RangeImageInTheRequest) {
  const Capture& c = meetingRoom();
  room_reverb::BuildRoomModel srv;
  srv.request.top = toMessage(c.images.top.color, ros::Time::now());
  srv.request.range = room_reverb::ros_bridge::imageToMessage(c.images.top.range_m, "32FC1", std_msgs::Header());
  srv.request.baseline_m = c.scene.options.baseline_m;
  ASSERT_TRUE(callBuild(srv));
  expectMeetingRoom(srv.response, "from_range");
}

TEST(VisualRouteNodes, BadRequestsFailWithAReason) {
  const Capture& c = meetingRoom();
  const auto expectRefused = [](room_reverb::BuildRoomModel& srv, const std::string& needle, const std::string& what) {
    ASSERT_TRUE(callBuild(srv)) << what;
    EXPECT_FALSE(srv.response.success) << what;
    EXPECT_NE(srv.response.message.find(needle), std::string::npos) << what << ": " << srv.response.message;
  };
  room_reverb::BuildRoomModel only_top;
  only_top.request.top = toMessage(c.images.top.color, ros::Time::now());
  expectRefused(only_top, "bottom image or a range image", "one image");

  room_reverb::BuildRoomModel both;
  both.request.top = toMessage(c.images.top.color, ros::Time::now());
  both.request.bottom = toMessage(c.images.bottom.color, ros::Time::now());
  both.request.range = toMessage(c.images.bottom.color, ros::Time::now());
  expectRefused(both, "not both", "bottom and range");

  room_reverb::BuildRoomModel colour_range;
  colour_range.request.top = toMessage(c.images.top.color, ros::Time::now());
  colour_range.request.range = toMessage(c.images.bottom.color, ros::Time::now());
  expectRefused(colour_range, "32FC1", "a colour image as the range");

  room_reverb::BuildRoomModel no_range;
  const cv::Mat invalid(kWidth / 2, kWidth, CV_32FC1, cv::Scalar(0.0f));
  no_range.request.top = toMessage(c.images.top.color, ros::Time::now());
  no_range.request.range = room_reverb::ros_bridge::imageToMessage(invalid, "32FC1", std_msgs::Header());
  expectRefused(no_range, "no valid", "a range image with no range");

  room_reverb::BuildRoomModel sizes;
  cv::Mat half;
  cv::resize(c.images.bottom.color, half, cv::Size(kWidth / 2, kWidth / 4));
  sizes.request.top = toMessage(c.images.top.color, ros::Time::now());
  sizes.request.bottom = toMessage(half, ros::Time::now());
  expectRefused(sizes, "size", "different sizes");

  room_reverb::BuildRoomModel black;
  const cv::Mat dark(kWidth / 2, kWidth, CV_8UC3, cv::Scalar::all(0));
  black.request.top = toMessage(dark, ros::Time::now());
  black.request.bottom = toMessage(dark, ros::Time::now());
  expectRefused(black, "black", "black pair");

  room_reverb::BuildRoomModel square;
  const cv::Mat sq(kWidth / 2, kWidth / 2, CV_8UC3, cv::Scalar::all(128));
  square.request.top = toMessage(sq, ros::Time::now());
  square.request.bottom = toMessage(sq, ros::Time::now());
  expectRefused(square, "twice as wide", "not 2:1");

  room_reverb::BuildRoomModel zero_baseline;
  zero_baseline.request.top = toMessage(c.images.top.color, ros::Time::now());
  zero_baseline.request.bottom = toMessage(c.images.bottom.color, ros::Time::now());
  zero_baseline.request.baseline_m = -0.2;
  expectRefused(zero_baseline, "baseline", "negative baseline");

  // Still serving after all that.
  room_reverb::BuildRoomModel good;
  good.request.top = toMessage(c.images.top.color, ros::Time::now());
  good.request.bottom = toMessage(c.images.bottom.color, ros::Time::now());
  ASSERT_TRUE(callBuild(good));
  EXPECT_TRUE(good.response.success) << good.response.message;
}

TEST(VisualRouteNodes, MaterialsOverrideParameter) {
  const Capture& c = meetingRoom();
  room_reverb::BuildRoomModel srv = pairRequest(c);
  room_reverb::BuildRoomModel missing = srv;
  ASSERT_TRUE(callBuild(srv, "/override/room_model/build"));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_EQ(srv.response.room.floor_material, "linoleum_on_concrete");
  ASSERT_EQ(srv.response.room.surface_confidence.size(), 6u);
  EXPECT_DOUBLE_EQ(srv.response.room.surface_confidence[0], 1.0);
  ASSERT_FALSE(srv.response.room.objects.empty());
  EXPECT_EQ(srv.response.room.objects[0].material, "door_wood");
  // The faces the file leaves alone keep what the camera saw.
  EXPECT_EQ(core::textureFamilyFor(srv.response.room.wall_y_min_material).family, core::TextureFamily::kGlass);

  ASSERT_TRUE(callBuild(missing, "/override_missing/room_model/build"));
  EXPECT_FALSE(missing.response.success);
  EXPECT_NE(missing.response.message.find("no_such_override.yaml"), std::string::npos) << missing.response.message;
}

TEST(VisualRouteNodes, NodeletGivesTheSameCloud) {
  ros::NodeHandle nh;
  const Capture& c = meetingRoom();
  // A black pair first: refused inside the nodelet, which must keep working.
  const cv::Mat dark(kWidth / 2, kWidth, CV_8UC3, cv::Scalar::all(0));
  EXPECT_FALSE(publishUntilCloud(nh, "/nodelet", dark, dark, 8.0));
  const auto cloud = publishUntilCloud(nh, "/nodelet", c.images.top.color, c.images.bottom.color, 60.0);
  ASSERT_TRUE(cloud) << "no cloud from the nodelet";
  EXPECT_EQ(cloud->header.frame_id, "rig");
  EXPECT_GT(static_cast<double>(cloud->width) * cloud->height, 0.8 * kWidth * kWidth / 2 * 0.8);
}

TEST(VisualRouteNodes, TiltedRigThroughTheWholeChain) {
  ros::NodeHandle nh;
  const Capture& c = tiltedMeetingRoom();
  Latest<geometry_msgs::QuaternionStamped> tilt, rotation;
  auto tilt_sub = nh.subscribe("/chain/rig_tilt", 1, &Latest<geometry_msgs::QuaternionStamped>::on, &tilt);
  auto rotation_sub =
      nh.subscribe("/chain/capture_ingest/image_rotation", 1, &Latest<geometry_msgs::QuaternionStamped>::on, &rotation);
  auto top_pub = nh.advertise<sensor_msgs::Image>("/chain/top/image_raw", 1);
  auto bottom_pub = nh.advertise<sensor_msgs::Image>("/chain/bottom/image_raw", 1);
  Latest<sensor_msgs::PointCloud2> cloud;
  auto cloud_sub = nh.subscribe("/chain/points", 1, &Latest<sensor_msgs::PointCloud2>::on, &cloud);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(90.0);
  ros::WallTime next_publish = ros::WallTime::now();
  while (ros::WallTime::now() < deadline && !cloud.get()) {
    if (ros::WallTime::now() >= next_publish && top_pub.getNumSubscribers() > 0 && bottom_pub.getNumSubscribers() > 0) {
      const ros::Time stamp = ros::Time::now();
      top_pub.publish(toMessage(c.images.top.fisheye, stamp));
      bottom_pub.publish(toMessage(c.images.bottom.fisheye, stamp));
      next_publish = ros::WallTime::now() + ros::WallDuration(5.0);
    }
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_TRUE(cloud.get()) << "no cloud at the end of the chain";
  ASSERT_TRUE(tilt.get());
  ASSERT_TRUE(rotation.get());
  const double tilt_deg = Eigen::AngleAxisd(toEigen(tilt.get()->quaternion)).angle() * 180.0 / kPi;
  EXPECT_NEAR(tilt_deg, 3.0, 0.5);
  ::testing::Test::RecordProperty("chain_tilt_deg", std::to_string(tilt_deg));

  ros::WallDuration(0.5).sleep();
  room_reverb::BuildRoomModel srv;
  ASSERT_TRUE(callBuild(srv, "/chain/room_model/build", true));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const core::RoomModel& truth = c.scene.room;
  const double got[3] = {srv.response.room.size.x, srv.response.room.size.y, srv.response.room.size.z};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(got[k], truth.size_m[k], std::max(0.03, 0.01 * truth.size_m[k])) << "axis " << k;
  }
  // The rig's pose in the room: room <- aligned rig (the service) <- camera (the turn the
  // images were given) against the rendered rig rotation.
  const Eigen::Quaterniond camera_in_room =
      toEigen(srv.response.room_to_rig.transform.rotation) * toEigen(rotation.get()->quaternion);
  const double pose_error_deg = camera_in_room.angularDistance(truth.rig_rotation) * 180.0 / kPi;
  EXPECT_LT(pose_error_deg, 1.0);
  ::testing::Test::RecordProperty("chain_pose_error_deg", std::to_string(pose_error_deg));
  ::testing::Test::RecordProperty("chain_message", srv.response.message);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_visual_route_nodes");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  meetingRoom();  // render once, before the tests' clocks start
  tiltedMeetingRoom();
  return RUN_ALL_TESTS();
}
