// Dual-fisheye lenses: the equidistant projection both ways, the calibration file, and
// stitching a rendered dual-fisheye capture back to the generator's own equirect image.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <random>

#include "room_reverb/common/error.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/dual_fisheye.h"
#include "room_reverb/vision/equirect.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;
using room_reverb::test::tempPath;
using room_reverb::test::writeFile;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

DualFisheyeCalibration shippedCalibration() {
  return loadDualFisheyeCalibration(std::string(ROOM_REVERB_SOURCE_DIR) + "/config/dual_fisheye.yaml");
}

double percentile(std::vector<double> values, double fraction) {
  const auto at = values.begin() + static_cast<long>(fraction * (values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

}  // namespace

TEST(DualFisheye, NominalLensesLookForwardAndBackWithImageUpAlongZ) {
  const DualFisheyeCalibration c = idealDualFisheye(1000);
  const FisheyeLens& front = c.front;
  // The axis lands on the principal point; the fov/2 ray on the circle.
  EXPECT_LT((*fisheyeProject(front, FisheyeSide::kFront, Eigen::Vector3d::UnitX()) - front.center_px).norm(), 1e-9);
  const Eigen::Vector3d edge(std::cos(95 * kDeg), 0.0, std::sin(95 * kDeg));
  const Eigen::Vector2d top = *fisheyeProject(front, FisheyeSide::kFront, edge);
  EXPECT_NEAR(top.x(), 500.0, 1e-9);
  EXPECT_NEAR(top.y(), 500.0 - 480.0, 1e-9);  // up in the world is up in the image
  // Front: the camera's left (+y) is the image's left; back: its right.
  EXPECT_LT(fisheyeProject(front, FisheyeSide::kFront, Eigen::Vector3d(1, 0.3, 0))->x(), 500.0);
  EXPECT_GT(fisheyeProject(c.back, FisheyeSide::kBack, Eigen::Vector3d(-1, 0.3, 0))->x(), 500.0);
  EXPECT_LT((*fisheyeProject(c.back, FisheyeSide::kBack, -Eigen::Vector3d::UnitX()) - c.back.center_px).norm(), 1e-9);
  // Beyond half the field of view, and outside the circle, there is nothing.
  EXPECT_FALSE(fisheyeProject(front, FisheyeSide::kFront, -Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(fisheyeUnproject(front, FisheyeSide::kFront, Eigen::Vector2d(5, 5)));
  EXPECT_NEAR(fisheyeAngleFromAxis(front, FisheyeSide::kFront, Eigen::Vector3d::UnitZ()), 90 * kDeg, 1e-12);
}

TEST(DualFisheye, ProjectionAndUnprojectionAreInverse) {
  const DualFisheyeCalibration c = shippedCalibration();
  std::mt19937 random(5);
  std::normal_distribution<double> gauss;
  int tested = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
    for (const FisheyeSide side : {FisheyeSide::kFront, FisheyeSide::kBack}) {
      const auto pixel = fisheyeProject(c.lens(side), side, d);
      if (!pixel) continue;
      const auto back = fisheyeUnproject(c.lens(side), side, *pixel);
      ASSERT_TRUE(back);
      EXPECT_LT((*back - d).norm(), 1e-9);
      ++tested;
    }
  }
  EXPECT_GT(tested, 2000);  // the overlap is seen twice
}

TEST(DualFisheye, CalibrationFileRoundTripsAndRejectsBadValues) {
  const DualFisheyeCalibration shipped = shippedCalibration();
  EXPECT_EQ(shipped.size_px, 1024);
  EXPECT_NE(shipped.front.rotation_rpy_deg, Eigen::Vector3d::Zero());  // a realistic, imperfect camera
  const std::string path = tempPath("calibration.yaml").string();
  saveDualFisheyeCalibration(path, shipped);
  const DualFisheyeCalibration again = loadDualFisheyeCalibration(path);
  EXPECT_EQ(again.front.center_px, shipped.front.center_px);
  EXPECT_EQ(again.back.radius_px, shipped.back.radius_px);
  EXPECT_EQ(again.back.rotation_rpy_deg, shipped.back.rotation_rpy_deg);

  const DualFisheyeCalibration half = scaledDualFisheye(shipped, 512);
  EXPECT_DOUBLE_EQ(half.front.radius_px, 0.5 * shipped.front.radius_px);
  EXPECT_EQ(half.front.fov_deg, shipped.front.fov_deg);

  expectInputError([] { parseDualFisheyeCalibration("size_px: 512\nfront: {fov_deg: 170}\n", "cal.yaml"); },
                   {"cal.yaml", "front.fov_deg", "between 180 and 360"});
  expectInputError([] { parseDualFisheyeCalibration("size_px: 512\nback: {center_px: [600, 10]}\n", "cal.yaml"); },
                   {"back.center_px", "inside"});
  expectInputError([] { parseDualFisheyeCalibration("size_px: 512.5\n", "cal.yaml"); }, {"size_px", "whole number"});
  expectInputError([] { loadDualFisheyeCalibration("/nonexistent/cal.yaml"); }, {"/nonexistent/cal.yaml", "no such file"});
}

TEST(DualFisheye, StitchingARenderedCaptureMatchesTheEquirectRender) {
  const CaptureScene scene = loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/kt.yaml");
  CaptureOptions options = scene.options;
  options.width = 512;
  options.fisheye = true;
  options.fisheye_calibration = shippedCalibration();
  const StereoCapture capture = renderCapture(scene.room, MaterialLibrary::loadDefault(), options);
  ASSERT_EQ(capture.top.fisheye.cols, 512);
  ASSERT_EQ(capture.top.fisheye.rows, 256);
  const cv::Mat stitched = fisheyeToEquirect(capture.top.fisheye, options.fisheye_calibration, 512);
  ASSERT_EQ(stitched.type(), CV_8UC3);
  ASSERT_EQ(stitched.size(), capture.top.color.size());

  const EquirectGeometry g{512, 256};
  // Per-pixel error against the generator's equirect render, split at the seam: within 8°
  // of the plane between the lenses (the 10° overlap plus the lenses' tilts).
  const auto errors = [&](const cv::Mat& stitched_image, std::vector<double>& away, std::vector<double>& seam) {
    for (int v = 0; v < g.height; ++v) {
      for (int u = 0; u < g.width; ++u) {
        const cv::Vec3b a = stitched_image.at<cv::Vec3b>(v, u), b = capture.top.color.at<cv::Vec3b>(v, u);
        const double error = (std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2])) / 3.0;
        const bool near_seam = std::abs(equirectPixelDirection(g, u, v).x()) < std::sin(8 * kDeg);
        (near_seam ? seam : away).push_back(error);
      }
    }
  };
  std::vector<double> away, seam, away_ideal, seam_ideal;
  errors(stitched, away, seam);
  const double away_median = percentile(away, 0.5), seam_median = percentile(seam, 0.5);
  std::cout << "stitching median absolute error: " << away_median << " grey levels away from the seam, " << seam_median
            << " at the seam, 90th percentile " << percentile(away, 0.9) << "\n";
  EXPECT_LE(away_median, 3.0);
  EXPECT_LE(seam_median, 6.0);
  // The median alone would pass a slightly wrong calibration: stitching the same images
  // as if the lenses were ideal (centred, untilted) must be clearly worse in the tail.
  errors(fisheyeToEquirect(capture.top.fisheye, scaledDualFisheye(idealDualFisheye(1024), 256), 512), away_ideal,
         seam_ideal);
  // Measured 4.3 grey levels at 512 wide on this scene (its tiles' grout lines are the
  // sharpest detail); the ideal calibration gives more than 1.4 times that.
  EXPECT_LE(percentile(away, 0.9), 5.0);
  EXPECT_GT(percentile(away_ideal, 0.9), 1.4 * percentile(away, 0.9));
}

TEST(DualFisheye, StitchingRejectsBadInputs) {
  const DualFisheyeCalibration c = idealDualFisheye(64);
  expectInputError([&] { fisheyeToEquirect(cv::Mat(64, 64, CV_8UC3), c, 256); }, {"64 x 64", "2S x S"});
  expectInputError([&] { fisheyeToEquirect(cv::Mat(), c, 256); }, {"2S x S"});
  expectInputError([&] { fisheyeToEquirect(cv::Mat(64, 128, CV_8UC3), c, 255); }, {"width 255"});
  // A calibration for another size is scaled to the image.
  const cv::Mat stitched = fisheyeToEquirect(cv::Mat(64, 128, CV_8UC3, cv::Scalar(50, 100, 150)), idealDualFisheye(1024), 128);
  EXPECT_EQ(stitched.at<cv::Vec3b>(32, 64), cv::Vec3b(50, 100, 150));
}
