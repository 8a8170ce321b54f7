// Levelling from the cloud (vision/cloud_leveling.h) and the capture's fall-back to it
// (vision/capture_ingest.h): scans of rooms (test/support/room_scan.h, cluttered_rooms.h)
// from rigs tilted by known angles; images with edges but no Manhattan structure are
// levelled by the cloud with a warning, black images are still refused.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "room_reverb/synthetic_capture/cluttered_rooms.h"
#include "room_reverb/vision/capture_ingest.h"
#include "room_reverb/vision/cloud_leveling.h"
#include "room_scan.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::stereoLikeScanOptions;
using room_reverb::test::expectInputError;
using room_reverb::test::scanRoomModel;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The angle between the up the levelling finds and the true up, both in the rig frame.
double upError(const RoomModel& scanned, const CloudLeveling& leveling) {
  const Eigen::Vector3d true_up = scanned.rig_rotation.conjugate() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d found_up = leveling.tilt.transpose() * Eigen::Vector3d::UnitZ();
  return std::acos(std::clamp(true_up.dot(found_up), -1.0, 1.0));
}

RoomModel tilted(RoomModel model, double about_deg, double tilt_deg) {
  const Eigen::Vector3d axis(std::cos(about_deg * kDeg), std::sin(about_deg * kDeg), 0.0);
  model.rig_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(tilt_deg * kDeg, axis)) * model.rig_rotation;
  return model;
}

}  // namespace

TEST(CloudLeveling, TiltedRigsInClutteredRooms) {
  // Tilts a tripod set by hand reaches, about several horizontal axes.
  const double tilts[][2] = {{0.0, 0.0}, {30.0, 2.0}, {120.0, 4.0}, {250.0, 6.5}};
  int index = 1;
  for (const auto& t : tilts) {
    const RoomModel room = tilted(clutteredRoom(ClutterSet::kDevelopment, index++).scanned, t[0], t[1]);
    const CloudLeveling leveling = levelFromCloud(scanRoomModel(room, stereoLikeScanOptions(3)).cloud);
    std::printf("[ measured ] rig tilt %.1f deg about %.0f deg: found %.2f deg, up error %.3f deg\n", t[1], t[0],
                leveling.tilt_rad / kDeg, upError(room, leveling) / kDeg);
    EXPECT_LE(upError(room, leveling), 0.15 * kDeg) << t[1] << " about " << t[0];
    EXPECT_NEAR(leveling.tilt_rad / kDeg, t[1], 0.15);
  }
}

TEST(CloudLeveling, BadInput) {
  expectInputError([] { levelFromCloud(PointCloud{}); }, {"empty"});
  PointCloud few;
  few.points.resize(10);
  expectInputError([&] { levelFromCloud(few); }, {"too few points (10"});
  CloudLevelingOptions bad;
  bad.max_tilt_rad = 2.0;
  expectInputError([&] { levelFromCloud(few, bad); }, {"max_tilt_rad"});
}

TEST(CaptureIngest, ImagesWithoutManhattanStructureFallBackToTheCloud) {
  // Blurred noise has edges (streaks through the poles) but no second direction.
  cv::Mat blobs(512, 1024, CV_8UC1);
  cv::RNG rng(7);
  rng.fill(blobs, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(blobs, blobs, cv::Size(0, 0), 8.0);
  cv::normalize(blobs, blobs, 0, 255, cv::NORM_MINMAX);
  const IngestedCapture capture = ingestCapture(blobs, blobs, CaptureIngestOptions{});
  EXPECT_TRUE(capture.level_from_cloud);
  ASSERT_EQ(capture.warnings.size(), 1u);
  EXPECT_NE(capture.warnings.front().find("no Manhattan structure"), std::string::npos);
  EXPECT_TRUE(capture.leveling.tilt.isIdentity());
  // A black pair has no edges at all: refused as before.
  const cv::Mat black(512, 1024, CV_8UC3, cv::Scalar::all(0));
  expectInputError([&] { ingestCapture(black, black, CaptureIngestOptions{}); }, {"0 straight line segments"});
}
