// Vertical-baseline spherical stereo on generated captures with known range: accuracy,
// coverage outside the polar caps, the sine rule, and bad input. Run at 1024 x 512 to stay
// fast; bench_visual_route measures 2048 x 1024, the size the targets are set for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/spherical_stereo.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct DepthScore {
  double valid_fraction = 0.0;  // outside the polar caps
  double median = 0.0, p90 = 0.0;  // relative range error on valid pixels
};

DepthScore score(const SphericalDepth& depth, const cv::Mat& truth, double cap_deg) {
  std::vector<double> errors;
  long outside = 0, valid = 0;
  for (int v = 0; v < truth.rows; ++v) {
    const double theta = (v + 0.5) * kPi / truth.rows;
    if (theta < cap_deg * kPi / 180.0 || theta > kPi - cap_deg * kPi / 180.0) continue;
    for (int u = 0; u < truth.cols; ++u) {
      ++outside;
      if (depth.valid.at<std::uint8_t>(v, u) == 0) continue;
      ++valid;
      const double t = truth.at<float>(v, u);
      errors.push_back(std::abs(depth.range_m.at<float>(v, u) - t) / t);
    }
  }
  std::sort(errors.begin(), errors.end());
  DepthScore s;
  s.valid_fraction = static_cast<double>(valid) / static_cast<double>(outside);
  if (!errors.empty()) {
    s.median = errors[errors.size() / 2];
    s.p90 = errors[errors.size() * 9 / 10];
  }
  return s;
}

StereoCapture render(const std::string& scene_name, int width) {
  CaptureScene scene = loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/" + scene_name + ".yaml");
  scene.options.width = width;
  return renderCapture(scene.room, MaterialLibrary::loadDefault(), scene.options);
}

}  // namespace

TEST(SphericalStereo, SineRuleGivesTheRangeOfAKnownPoint) {
  // A point 2 m from the top camera, 30 degrees below the horizon; the bottom camera 0.2 m
  // lower sees it at a smaller depression.
  const double b = 0.2, r = 2.0, theta_t = kPi / 2.0 + kPi / 6.0;
  const Eigen::Vector2d p(r * std::sin(theta_t), r * std::cos(theta_t) + b);  // relative to the bottom camera
  const double theta_b = std::atan2(p.x(), p.y());
  EXPECT_NEAR(rangeFromDisparity(theta_t, theta_t - theta_b, b), r, 1e-12);
  EXPECT_TRUE(std::isnan(rangeFromDisparity(theta_t, 0.0, b)));
}

TEST(SphericalStereo, RangesOfThePaperMeetingRoomWithinTolerance) {
  const StereoCapture capture = render("mr", 1024);
  const SphericalStereoOptions options;
  const SphericalDepth depth = computeSphericalDepth(capture.top.color, capture.bottom.color, 0.2, options);
  const DepthScore s = score(depth, capture.top.range_m, options.polar_cap_deg);
  std::cout << "MR 1024x512: valid " << 100.0 * s.valid_fraction << " %, median " << 100.0 * s.median << " %, p90 "
            << 100.0 * s.p90 << " %\n";
  // The targets (median 2 %, p90 5 %, 90 % valid) are for 2048 x 1024; at half the
  // resolution the disparities are half as large and the p90 is allowed 6 %.
  EXPECT_GE(s.valid_fraction, 0.90);
  EXPECT_LE(s.median, 0.02);
  EXPECT_LE(s.p90, 0.06);
  // The range image is in the top image's geometry; invalid pixels are NaN.
  EXPECT_EQ(depth.range_m.size(), capture.top.color.size());
  EXPECT_TRUE(std::isnan(depth.range_m.at<float>(0, 0)));  // the zenith cap
}

TEST(SphericalStereo, FurnitureRoomAndASeamThatIsNoBarrier) {
  const StereoCapture capture = render("lounge_furniture", 1024);
  const SphericalStereoOptions options;
  const SphericalDepth depth = computeSphericalDepth(capture.top.color, capture.bottom.color, 0.2, options);
  const DepthScore s = score(depth, capture.top.range_m, options.polar_cap_deg);
  std::cout << "lounge 1024x512: valid " << 100.0 * s.valid_fraction << " %, median " << 100.0 * s.median
            << " %, p90 " << 100.0 * s.p90 << " %\n";
  EXPECT_GE(s.valid_fraction, 0.95);
  EXPECT_LE(s.median, 0.02);
  EXPECT_LE(s.p90, 0.05);
  // The columns either side of the +-180 degree seam are measured like any others.
  int seam_valid = 0, rows = 0;
  for (int v = 128; v < 384; ++v, ++rows) {
    seam_valid += depth.valid.at<std::uint8_t>(v, 0) != 0 && depth.valid.at<std::uint8_t>(v, 1023) != 0;
  }
  EXPECT_GE(seam_valid, rows * 9 / 10);
}

TEST(SphericalStereo, BadInput) {
  const cv::Mat textured = [] {
    cv::Mat m(64, 128, CV_8UC3);
    cv::randu(m, 0, 255);
    return m;
  }();
  expectInputError([&] { computeSphericalDepth(cv::Mat(), textured, 0.2); }, {"empty"});
  expectInputError([&] { computeSphericalDepth(textured, cv::Mat(32, 64, CV_8UC3, cv::Scalar(9)), 0.2); },
                   {"differ in size", "128x64", "64x32"});
  expectInputError([&] { computeSphericalDepth(cv::Mat(64, 100, CV_8UC3), cv::Mat(64, 100, CV_8UC3), 0.2); },
                   {"twice as wide", "100x64"});
  expectInputError([&] { computeSphericalDepth(textured, cv::Mat(64, 128, CV_8UC3, cv::Scalar::all(0)), 0.2); }, {"bottom", "black"});
  expectInputError([&] { computeSphericalDepth(cv::Mat(64, 128, CV_8UC3, cv::Scalar::all(255)), textured, 0.2); }, {"top", "saturated"});
  expectInputError([&] { computeSphericalDepth(textured, textured, 0.0); }, {"baseline"});
  expectInputError([&] { computeSphericalDepth(textured, textured, std::nan("")); }, {"baseline"});
  cv::Mat grey;
  cv::cvtColor(textured, grey, cv::COLOR_BGR2GRAY);
  expectInputError([&] { computeSphericalDepth(textured, grey, 0.2); }, {"type"});
  SphericalStereoOptions bad;
  bad.block_size = 4;
  expectInputError([&] { computeSphericalDepth(textured, textured, 0.2, bad); }, {"block_size"});
  SphericalStereoOptions small_tiles;
  small_tiles.planar_tile_px = 4;
  expectInputError([&] { computeSphericalDepth(textured, textured, 0.2, small_tiles); }, {"planar_tile_px"});
  SphericalStereoOptions no_range;
  no_range.planar_max_range_m = std::nan("");
  expectInputError([&] { computeSphericalDepth(textured, textured, 0.2, no_range); }, {"planar_max_range_m"});
}

// Two cameras on auto-exposure: the bottom one a third of a stop darker and white-balanced
// warmer. The matcher's pairs say how the exposures differ; matched again with the bottom
// image carried onto the top's, the pair is ranged as one exposed alike.
TEST(SphericalStereo, CamerasExposedOnTheirOwnRangeAsOneExposedAlike) {
  CaptureScene scene = loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/mr.yaml");
  scene.options.width = 1024;
  const StereoCapture alike = renderCapture(scene.room, MaterialLibrary::loadDefault(), scene.options);
  scene.options.camera.bottom_exposure = 0.79;
  scene.options.camera.bottom_white_balance = {1.08, 1.0, 0.92};
  const StereoCapture apart = renderCapture(scene.room, MaterialLibrary::loadDefault(), scene.options);
  SphericalStereoOptions options;
  const DepthScore reference = score(computeSphericalDepth(alike.top.color, alike.bottom.color, 0.2, options), alike.top.range_m,
                                     options.polar_cap_deg);
  const DepthScore matched = score(computeSphericalDepth(apart.top.color, apart.bottom.color, 0.2, options), apart.top.range_m,
                                   options.polar_cap_deg);
  options.match_exposure = false;
  const DepthScore unmatched = score(computeSphericalDepth(apart.top.color, apart.bottom.color, 0.2, options),
                                     apart.top.range_m, options.polar_cap_deg);
  // A pair exposed alike is matched once, as without the option: the same ranges.
  const SphericalDepth once = computeSphericalDepth(alike.top.color, alike.bottom.color, 0.2, options);
  options.match_exposure = true;
  const SphericalDepth checked = computeSphericalDepth(alike.top.color, alike.bottom.color, 0.2, options);
  EXPECT_EQ(cv::norm(once.valid, checked.valid, cv::NORM_INF), 0.0);
  cv::Mat a, b;
  once.range_m.copyTo(a, once.valid), checked.range_m.copyTo(b, checked.valid);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  std::cout << "MR 1024x512 valid, median range error: exposed alike " << 100.0 * reference.valid_fraction << " %, "
            << 100.0 * reference.median << " %; bottom 1/3 stop darker " << 100.0 * matched.valid_fraction << " %, "
            << 100.0 * matched.median << " % (without matching the exposure " << 100.0 * unmatched.valid_fraction << " %, "
            << 100.0 * unmatched.median << " %)\n";
  // Within a tenth of a percentage point of the median error (measured 0.55 against 0.49 %;
  // the exposure map's residual mismatch is what the tiles' planes, fitted to grey levels,
  // still see).
  EXPECT_LE(matched.median, reference.median + 0.001);
  EXPECT_GE(matched.valid_fraction, reference.valid_fraction - 0.01);
  // Without it the matcher loses a sixth of the room.
  EXPECT_LE(unmatched.valid_fraction, reference.valid_fraction - 0.1);
}

// The matcher works only on the polar angles between the caps (and the margins its search
// and paths need): the rows right next to each cap are ranged like the rest, whatever the
// cap's size.
TEST(SphericalStereo, RowsNextToThePolarCapsAreRanged) {
  const StereoCapture capture = render("mr", 1024);
  for (const double cap_deg : {15.0, 30.0}) {
    SphericalStereoOptions options;
    options.polar_cap_deg = cap_deg;
    const SphericalDepth depth = computeSphericalDepth(capture.top.color, capture.bottom.color, 0.2, options);
    for (const bool zenith_side : {true, false}) {
      long pixels = 0;
      std::vector<double> errors;
      for (int v = 0; v < depth.range_m.rows; ++v) {
        const double polar_deg = (v + 0.5) * 180.0 / depth.range_m.rows;
        const double from_cap_deg = zenith_side ? polar_deg - cap_deg : 180.0 - cap_deg - polar_deg;
        if (from_cap_deg < 0.0 || from_cap_deg >= 3.0) continue;
        for (int u = 0; u < depth.range_m.cols; ++u, ++pixels) {
          if (depth.valid.at<std::uint8_t>(v, u) == 0) continue;
          const double truth = capture.top.range_m.at<float>(v, u);
          errors.push_back(std::abs(depth.range_m.at<float>(v, u) - truth) / truth);
        }
      }
      ASSERT_GT(pixels, 0);
      std::sort(errors.begin(), errors.end());
      const std::string where = std::to_string(int(cap_deg)) + " deg cap, " + (zenith_side ? "zenith" : "nadir") + " side";
      EXPECT_GE(static_cast<double>(errors.size()) / static_cast<double>(pixels), 0.95) << where;
      ASSERT_FALSE(errors.empty()) << where;
      EXPECT_LE(errors[errors.size() / 2], 0.03) << where;
    }
    // Inside the caps there is no range.
    EXPECT_EQ(cv::countNonZero(depth.valid.rowRange(0, static_cast<int>(cap_deg / 180.0 * depth.range_m.rows) - 1)), 0);
  }
}

namespace {

// Of one surface's pixels outside the polar caps: the share ranged, and the share ranged
// more than 10 % wrong.
struct SurfaceScore {
  double ranged = 0.0, wrong = 0.0;
};

SurfaceScore surfaceScore(const SphericalDepth& depth, const StereoCapture& capture, const std::string& surface, double cap_deg) {
  const auto found = std::find(capture.object_names.begin(), capture.object_names.end(), surface);
  EXPECT_NE(found, capture.object_names.end()) << surface;
  const int id = static_cast<int>(found - capture.object_names.begin());  // object_id holds the index
  long pixels = 0, ranged = 0, wrong = 0;
  for (int v = 0; v < depth.range_m.rows; ++v) {
    const double theta = (v + 0.5) * kPi / depth.range_m.rows;
    if (theta < cap_deg * kPi / 180.0 || theta > kPi - cap_deg * kPi / 180.0) continue;
    for (int u = 0; u < depth.range_m.cols; ++u) {
      if (capture.top.object_id.at<std::uint16_t>(v, u) != id) continue;
      ++pixels;
      if (depth.valid.at<std::uint8_t>(v, u) == 0) continue;
      ++ranged;
      const double truth = capture.top.range_m.at<float>(v, u);
      wrong += std::abs(depth.range_m.at<float>(v, u) - truth) > 0.1 * truth;
    }
  }
  SurfaceScore s;
  if (pixels > 0) s.ranged = double(ranged) / double(pixels), s.wrong = double(wrong) / double(pixels);
  return s;
}

}  // namespace

// The plain office's gypsum wall is drawn nearly flat (capture.low_texture_contrast), and
// the cameras add 3 grey levels of noise: the matcher, left to itself, ranges most of the
// wall smoothly and wrongly, which a layout cannot tell from a wall. The pixels whose
// texture the noise drowns get no range instead.
TEST(SphericalStereo, APlainWallUnderNoiseIsLeftUnrangedNotRangedWrong) {
  CaptureScene scene = loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/plain_office.yaml");
  scene.options.width = 1024;
  scene.options.noise_sigma = 3.0;
  const StereoCapture capture = renderCapture(scene.room, MaterialLibrary::loadDefault(), scene.options);
  SphericalStereoOptions keeping_all;
  keeping_all.min_texture_snr = 0.0;
  const SphericalStereoOptions options;
  const SphericalDepth all = computeSphericalDepth(capture.top.color, capture.bottom.color, 0.2, keeping_all);
  const SphericalDepth depth = computeSphericalDepth(capture.top.color, capture.bottom.color, 0.2, options);
  const SurfaceScore wall_all = surfaceScore(all, capture, "wall_x_max", options.polar_cap_deg);
  const SurfaceScore wall = surfaceScore(depth, capture, "wall_x_max", options.polar_cap_deg);
  const SurfaceScore floor = surfaceScore(depth, capture, "floor", options.polar_cap_deg);
  const SurfaceScore floor_all = surfaceScore(all, capture, "floor", options.polar_cap_deg);
  std::cout << "plain wall under noise 3: every match " << 100.0 * wall_all.ranged << " % ranged, "
            << 100.0 * wall_all.wrong << " % over 10 % wrong; textured matches " << 100.0 * wall.ranged << " % ranged, "
            << 100.0 * wall.wrong << " % wrong; floor " << 100.0 * floor_all.ranged << " / " << 100.0 * floor.ranged
            << " % ranged\n";
  EXPECT_GE(wall_all.wrong, 0.2);  // the failure this guards against
  EXPECT_LE(wall.wrong, 0.05);
  // The carpet, matched right everywhere, loses some of its ranges too (92 % of it ranged
  // against 100 % at this size): the price of the test.
  EXPECT_GE(floor.ranged, 0.9);
  EXPECT_LE(floor.wrong, floor_all.wrong + 0.002);
}

TEST(SphericalStereo, TextureTestOptionsOutOfRangeAreRefused) {
  cv::Mat textured(64, 128, CV_8UC3);
  cv::randu(textured, 0, 255);
  SphericalStereoOptions negative;
  negative.min_texture_snr = -1.0;
  expectInputError([&] { computeSphericalDepth(textured, textured, 0.2, negative); }, {"min_texture_snr"});
  SphericalStereoOptions not_a_number;
  not_a_number.min_texture_snr = std::nan("");
  expectInputError([&] { computeSphericalDepth(textured, textured, 0.2, not_a_number); }, {"min_texture_snr"});
  SphericalStereoOptions no_window;
  no_window.texture_half_window_px = 0;
  expectInputError([&] { computeSphericalDepth(textured, textured, 0.2, no_window); }, {"texture_half_window_px"});
}
