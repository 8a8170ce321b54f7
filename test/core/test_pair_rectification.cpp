// How the two cameras stand on the bar: the epipolar residual against exact geometry, the
// bottom camera's turn found on rendered pairs of the bundled rooms with known turns, a pair that stands true left alone, the route's box with and without
// the rectification, and bad input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/common/error.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/capture_ingest.h"
#include "room_reverb/vision/pair_rectification.h"
#include "room_reverb/vision/visual_route.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Eigen::Matrix3d turnOf(const Eigen::Vector3d& turn_deg) {
  return Eigen::AngleAxisd(turn_deg.norm() * kDeg, turn_deg.normalized()).toRotationMatrix();
}

CaptureScene scene(const std::string& name, int width) {
  CaptureScene s = loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/" + name + ".yaml");
  s.options.width = width;
  s.options.noise_sigma = 2.0;
  return s;
}

StereoCapture render(CaptureScene& s, const Eigen::Vector3d& top_turn_deg, const Eigen::Vector3d& bottom_turn_deg) {
  s.options.camera.top_turn_deg = top_turn_deg;
  s.options.camera.bottom_turn_deg = bottom_turn_deg;
  return renderCapture(s.room, MaterialLibrary::loadDefault(), s.options);
}

double angleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

// The worst of the box's three sizes against the truth, as a share.
double worstSizeError(const RoomModel& got, const RoomModel& truth) {
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(got.size_m[k] / truth.size_m[k] - 1.0));
  return worst;
}

}  // namespace

TEST(EpipolarResidual, ZeroForTwoViewsOfOnePointAndTheMissedAngleOtherwise) {
  const Eigen::Matrix3d R = turnOf({0.4, -1.1, 0.7});
  const Eigen::Vector3d t = Eigen::Vector3d(0.02, -0.01, 1.0).normalized();
  const Eigen::Vector3d top_centre = 0.1 * t, bottom_centre = -0.1 * t;
  for (const Eigen::Vector3d& point : {Eigen::Vector3d(3.0, 1.0, -1.2), Eigen::Vector3d(-2.0, 2.5, 1.1),
                                       Eigen::Vector3d(0.5, -4.0, 0.3)}) {
    const Eigen::Vector3d b_top = (point - top_centre).normalized();
    // The bottom camera's own frame: R takes it to the top camera's.
    const Eigen::Vector3d b_bottom = R.transpose() * (point - bottom_centre).normalized();
    EXPECT_NEAR(epipolarResidual(b_top, b_bottom, R, t), 0.0, 1e-12);
    // The top view turned out of the epipolar plane by 2 mrad about the plane's own
    // in-plane axis misses it by 2 mrad.
    const Eigen::Vector3d normal = t.cross(R * b_bottom).normalized();
    const Eigen::Vector3d axis = normal.cross(b_top).normalized();
    const Eigen::Vector3d off = Eigen::AngleAxisd(-0.002, axis) * b_top;
    EXPECT_NEAR(epipolarResidual(off, b_bottom, R, t), 0.002, 1e-9);
  }
}

TEST(PairRectification, FindsTheBottomCamerasTurnOnRenderedRooms) {
  struct Case {
    const char* room;
    Eigen::Vector3d top_turn_deg, bottom_turn_deg;
  };
  // Turns of a degree or so about every axis; the rig's own yaw (the top camera turned
  // about the bar) changes nothing the stereo sees.
  for (const Case& c : {Case{"mr", {0.0, 0.0, 0.0}, {0.3, -0.8, 0.5}}, Case{"mr", {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}},
                        Case{"kt", {0.0, 0.0, 0.8}, {-0.7, 0.2, -1.2}}, Case{"kt", {0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}},
                        Case{"lounge_furniture", {0.0, 0.0, 0.0}, {1.5, 0.4, 0.2}}}) {
    CaptureScene s = scene(c.room, 1024);
    const StereoCapture pair = render(s, c.top_turn_deg, c.bottom_turn_deg);
    const PairRectification found = estimatePairRectification(pair.top.color, pair.bottom.color);
    // The truth: the bottom camera's frame turned into the top one's.
    const double turn_error = angleBetween(found.bottom_to_top, turnOf(c.bottom_turn_deg));
    std::printf("[ measured ] %s: turn %.3f deg (truth %.3f), error %.3f mrad (se %.3f); %d of %d matches, "
                "residual %.2f mrad\n",
                c.room, found.turn_rad / kDeg, c.bottom_turn_deg.norm(), 1e3 * turn_error,
                1e3 * found.turn_standard_error_rad, found.inliers, found.matches, 1e3 * found.residual_rad);
    ASSERT_TRUE(found.estimated) << c.room;
    EXPECT_TRUE(found.applied) << c.room;
    // At 1024 px a match is placed within a fifth of a pixel (about 1 mrad); the turn
    // from hundreds of them within 0.1-1 mrad, errors the rooms' own (the fit's standard
    // error, 0.05-0.2 mrad, is smaller: the matches' errors are not independent).
    EXPECT_LT(turn_error, 1.2e-3) << c.room;
    EXPECT_LT(angleBetween(found.bottom_rotation, found.bottom_to_top), 1e-12);
  }
}

// Features found on the images shrunk to half their width and followed again at full
// size place the turn more closely than the shrunk images alone can (at half the mean
// error here); fewer features are found at half size, so not always as closely as
// features found at full size (above).
TEST(PairRectification, MatchesFoundShrunkAreFollowedAtFullSize) {
  double followed_sum = 0.0, shrunk_sum = 0.0, followed_worst = 0.0;
  int cases = 0;
  for (const auto& [room, turn] : {std::pair{"mr", Eigen::Vector3d(0.3, -0.8, 0.5)},
                                   std::pair{"kt", Eigen::Vector3d(-0.7, 0.2, -1.2)},
                                   std::pair{"lounge_furniture", Eigen::Vector3d(1.5, 0.4, 0.2)}}) {
    CaptureScene s = scene(room, 1024);
    const StereoCapture pair = render(s, Eigen::Vector3d::Zero(), turn);
    PairRectificationOptions half;
    half.feature_width = 512;
    const PairRectification followed = estimatePairRectification(pair.top.color, pair.bottom.color, half);
    cv::Mat top_small, bottom_small;
    cv::resize(pair.top.color, top_small, cv::Size(512, 256), 0, 0, cv::INTER_AREA);
    cv::resize(pair.bottom.color, bottom_small, cv::Size(512, 256), 0, 0, cv::INTER_AREA);
    const PairRectification shrunk = estimatePairRectification(top_small, bottom_small, half);
    ASSERT_TRUE(followed.estimated && shrunk.estimated) << room;
    const double followed_error = angleBetween(followed.bottom_to_top, turnOf(turn));
    const double shrunk_error = angleBetween(shrunk.bottom_to_top, turnOf(turn));
    std::printf("[ measured ] %s: turn error %.3f mrad followed at 1024 px, %.3f mrad at 512 px alone\n", room,
                1e3 * followed_error, 1e3 * shrunk_error);
    EXPECT_LT(followed_error, shrunk_error) << room;
    followed_sum += followed_error, shrunk_sum += shrunk_error, followed_worst = std::max(followed_worst, followed_error);
    ++cases;
  }
  // Measured 0.22-1.39 mrad (the lounge, whose half-size images give the fewest features).
  EXPECT_LT(followed_worst, 1.5e-3);
  EXPECT_LT(followed_sum / cases, 0.7 * shrunk_sum / cases);
}

TEST(PairRectification, APairThatStandsTrueIsLeftAlone) {
  for (const char* room : {"mr", "kt"}) {
    CaptureScene s = scene(room, 1024);
    const StereoCapture pair = render(s, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    const PairRectification found = estimatePairRectification(pair.top.color, pair.bottom.color);
    std::printf("[ measured ] %s standing true: turn %.3f mrad (se %.3f), %d inliers\n", room, 1e3 * found.turn_rad,
                1e3 * found.turn_standard_error_rad, found.inliers);
    ASSERT_TRUE(found.estimated) << room;
    EXPECT_FALSE(found.applied) << room;
    EXPECT_LT(found.turn_rad, 1e-3) << room;
    EXPECT_TRUE(found.bottom_rotation.isIdentity(0.0));
  }
}

TEST(PairRectification, TheRouteFitsTheBoxOfAPairWhoseCamerasStandTurned) {
  // The meeting room with its bottom camera tilted by 0.6 degrees and turned about the bar
  // by 0.4: the stereo's columns no longer meet, and half the room's disparities gain
  // 10 mrad while the other half lose them.
  CaptureScene s = scene("mr", 1024);
  const StereoCapture pair = render(s, {0.3, 0.2, 0.0}, {0.6, 0.0, 0.4});
  VisualRouteOptions route_options;
  loadDefaultMaterialModels(route_options);
  double worst[2] = {0.0, 0.0};
  for (const bool rectify : {true, false}) {
    CaptureIngestOptions ingest;
    ingest.rectification.enabled = rectify;
    const IngestedCapture ingested = ingestCapture(pair.top.color, pair.bottom.color, ingest);
    VisualRouteOptions options = route_options;
    options.level_from_cloud = ingested.level_from_cloud;
    RoomLayout layout;
    try {
      layout = runVisualRoute(ingested.top, ingested.bottom, s.options.baseline_m, options, ingested.leveling.tilt).layout;
    } catch (const InputError& e) {
      // As it comes, the pair may give no room at all.
      std::printf("[ measured ] meeting room, cameras turned, %s: refused (%s)\n",
                  rectify ? "rectified" : "as it comes", e.what());
      ASSERT_FALSE(rectify);
      worst[1] = 1.0;
      continue;
    }
    worst[rectify ? 0 : 1] = worstSizeError(layout.model, s.room);
    std::printf("[ measured ] meeting room, cameras turned, %s: %.3f x %.3f x %.3f m (truth %.3f x %.3f x %.3f)\n",
                rectify ? "rectified" : "as it comes", layout.model.size_m.x(), layout.model.size_m.y(),
                layout.model.size_m.z(), s.room.size_m.x(), s.room.size_m.y(), s.room.size_m.z());
    if (rectify) {
      ASSERT_TRUE(ingested.rectification.applied);
      bool warned = false;
      for (const std::string& w : ingested.warnings) warned = warned || w.find("the pair is rectified") != std::string::npos;
      EXPECT_TRUE(warned);
    }
  }
  EXPECT_LT(worst[0], 0.01);
  EXPECT_GT(worst[1], 0.03);
}

TEST(PairRectification, BadInputIsAClearError) {
  const cv::Mat image(256, 512, CV_8UC3, cv::Scalar(90, 100, 110));
  expectInputError([&] { estimatePairRectification(cv::Mat(), image); }, {"pair rectification", "empty"});
  expectInputError([&] { estimatePairRectification(image, cv::Mat(128, 256, CV_8UC3)); }, {"differ in size"});
  expectInputError([&] { estimatePairRectification(cv::Mat(100, 300, CV_8UC3), cv::Mat(100, 300, CV_8UC3)); },
                   {"twice as wide"});
  expectInputError([&] { estimatePairRectification(cv::Mat(128, 256, CV_16UC1), cv::Mat(128, 256, CV_16UC1)); },
                   {"8-bit"});
  PairRectificationOptions bad;
  bad.ratio = 1.5;
  expectInputError([&] { estimatePairRectification(image, image, bad); }, {"options out of range"});
  // A plain pair has nothing to match: no error, nothing estimated, nothing turned.
  const PairRectification plain = estimatePairRectification(image, image);
  EXPECT_FALSE(plain.estimated);
  EXPECT_FALSE(plain.applied);
  EXPECT_EQ(plain.matches, 0);
}
