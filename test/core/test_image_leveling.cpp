// Levelling 360-degree images: equirectangular rotation (round trip, exact column shifts,
// the seam and the poles, labels), the Manhattan frame of rendered rooms seen by a rig
// turned and tilted by known amounts, the yaw / tilt split that keeps the stereo baseline
// on the pole, the IMU route, and images without Manhattan structure. Rendered at 1024 x
// 512 to stay fast; the accuracy at 2048 x 1024 is in the report of the change (well
// under the 1 degree asked for at both sizes).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/equirect.h"
#include "room_reverb/vision/equirect_rotation.h"
#include "room_reverb/vision/image_leveling.h"
#include "room_reverb/vision/manhattan_from_image.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Eigen::Matrix3d rotZ(double rad) { return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

// Yaw about z, then pitch about y, then roll about x (in the rotated frames).
Eigen::Quaterniond yawPitchRoll(double yaw_deg, double pitch_deg, double roll_deg) {
  return Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX());
}

CaptureScene scene(const std::string& name, int width) {
  CaptureScene s = loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/" + name + ".yaml");
  s.options.width = width;
  s.options.supersampling = 1;
  return s;
}

// One camera at the scene's rig position, turned by `turn` after the scene's own rig
// rotation; returns the colour image, and the true rotation camera -> room in `truth`.
cv::Mat renderTurned(const CaptureScene& s, const Eigen::Quaterniond& turn, Eigen::Matrix3d* truth) {
  const Eigen::Quaterniond camera_to_room = s.room.rig_rotation * turn;
  *truth = camera_to_room.toRotationMatrix();
  return renderCaptureCamera(s.room, MaterialLibrary::loadDefault(), s.options, s.room.rig_position_m, camera_to_room).color;
}

// The room's axes are known only up to a quarter turn about z: the smallest angle between
// the estimate and the truth turned by k x 90 degrees, and its tilt (angle between the z
// axes) and yaw (turn about z) parts.
struct AngleError {
  double total_deg, tilt_deg, yaw_deg;
};

AngleError manhattanError(const Eigen::Matrix3d& estimate, const Eigen::Matrix3d& truth) {
  AngleError best{1e9, 0.0, 0.0};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Matrix3d difference = estimate * (rotZ(k * kPi / 2.0) * truth).transpose();
    const double angle = Eigen::AngleAxisd(difference).angle() / kDeg;
    if (angle < best.total_deg) {
      const ImageLeveling split = splitLeveling(difference);
      best = {angle, split.tilt_rad / kDeg, std::abs(split.yaw_rad) / kDeg};
    }
  }
  return best;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// A float image of a smooth function of the direction (a sum of low spherical harmonics),
// so the value any rotated image should hold at a pixel is known exactly.
double smoothField(const Eigen::Vector3d& d) {
  return 100.0 + 50.0 * d.x() + 40.0 * d.y() + 30.0 * d.y() * d.z() + 20.0 * d.z();
}

cv::Mat fieldImage(int width, const Eigen::Matrix3d& output_to_field) {
  const EquirectGeometry g{width, width / 2};
  cv::Mat image(g.height, g.width, CV_32FC1);
  for (int v = 0; v < g.height; ++v) {
    for (int u = 0; u < g.width; ++u) {
      image.at<float>(v, u) = static_cast<float>(smoothField(output_to_field * equirectPixelDirection(g, u, v)));
    }
  }
  return image;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// rotateEquirect

TEST(EquirectRotation, RoundTripGivesTheImageBack) {
  const CaptureScene s = scene("kt", 1024);
  Eigen::Matrix3d truth;
  const cv::Mat image = renderTurned(s, Eigen::Quaterniond::Identity(), &truth);
  const Eigen::Matrix3d R = yawPitchRoll(33.0, -12.0, 7.0).toRotationMatrix();
  const cv::Mat back = rotateEquirect(rotateEquirect(image, R, cv::INTER_LINEAR), R.transpose(), cv::INTER_LINEAR);
  ASSERT_EQ(back.size(), image.size());
  ASSERT_EQ(back.type(), image.type());
  cv::Mat difference;
  cv::absdiff(back, image, difference);
  difference = difference.reshape(1);
  std::vector<double> all, seam;
  double sum = 0.0;
  for (int v = 0; v < difference.rows; ++v) {
    for (int c = 0; c < difference.cols; ++c) {
      const double e = difference.at<std::uint8_t>(v, c);
      all.push_back(e);
      sum += e;
      const int u = c / 3;
      if (u < 4 || u >= image.cols - 4) seam.push_back(e);
    }
  }
  const double mean = sum / static_cast<double>(all.size());
  std::cout << "round trip (two bilinear resamplings): |error| median " << median(all) << ", mean " << mean
            << ", at the seam median " << median(seam) << " grey levels\n";
  // Two bilinear resamplings blur the texture a little; the seam is no worse than the rest.
  EXPECT_LE(median(all), 2.0);
  EXPECT_LE(mean, 4.0);
  EXPECT_LE(median(seam), 2.0);
}

TEST(EquirectRotation, TurnAboutZByWholePixelsIsAnExactColumnShift) {
  const int width = 256;
  cv::Mat colour(width / 2, width, CV_8UC3), labels(width / 2, width, CV_16UC1), range(width / 2, width, CV_32FC1);
  cv::randu(colour, 0, 256);
  cv::randu(labels, 0, 7);
  cv::randu(range, 0.5f, 9.0f);
  for (const int k : {1, 5, -17, 128}) {
    // A turn by k pixel angles brings azimuth phi to phi + k 2 pi / W: what was at column
    // u + k is now at u (azimuth falls with the column).
    const Eigen::Matrix3d R = rotZ(k * 2.0 * kPi / width);
    for (const cv::Mat& image : {colour, labels, range}) {
      for (const int interpolation : {cv::INTER_NEAREST, cv::INTER_LINEAR, cv::INTER_CUBIC}) {
        const cv::Mat out = rotateEquirect(image, R, interpolation);
        cv::Mat expected;
        const int shift = ((k % width) + width) % width;
        cv::hconcat(image.colRange(shift, width), image.colRange(0, shift), expected);
        EXPECT_EQ(cv::norm(out, expected, cv::NORM_INF), 0.0) << "k " << k << ", type " << image.type()
                                                              << ", interpolation " << interpolation;
      }
    }
  }
}

TEST(EquirectRotation, SamplesAcrossTheSeamAndThePolesOnTheSphere) {
  // A coarse image of a smooth field: any rotation must give the field rotated, including
  // the columns at the seam and the rows at the poles, which read pixels from the other
  // side of the seam or half a turn round the pole. (A border clamped to the edge column
  // or row would be off there by up to half a pixel's change of the field, about 2.5 here.)
  const int width = 64;
  const cv::Mat image = fieldImage(width, Eigen::Matrix3d::Identity());
  // (Turns about the pole alone, a fractional pixel's worth among them, take
  // rotateEquirect's shortcut for them.)
  for (const Eigen::Quaterniond& q : {yawPitchRoll(180.0, 0.0, 0.0), yawPitchRoll(-37.3, 0.0, 0.0), yawPitchRoll(40.0, 30.0, -20.0),
                                      yawPitchRoll(-100.0, 85.0, 10.0)}) {
    const Eigen::Matrix3d R = q.toRotationMatrix();
    const cv::Mat out = rotateEquirect(image, R, cv::INTER_LINEAR);
    const cv::Mat expected = fieldImage(width, R.transpose());
    double seam_error = 0.0, pole_error = 0.0, worst = 0.0;
    for (int v = 0; v < out.rows; ++v) {
      for (int u = 0; u < out.cols; ++u) {
        const double e = std::abs(out.at<float>(v, u) - expected.at<float>(v, u));
        worst = std::max(worst, e);
        if (u == 0 || u == width - 1) seam_error = std::max(seam_error, e);
        if (v == 0 || v == out.rows - 1) pole_error = std::max(pole_error, e);
      }
    }
    // What is left is bilinear interpolation's own error on a 5.6 degree grid.
    EXPECT_LE(worst, 1.0);
    EXPECT_LE(seam_error, 1.0);
    EXPECT_LE(pole_error, 1.0);
  }
  // Turning by half a pixel's angle: the seam columns interpolate between the last and the
  // first column, like any other pair of neighbours.
  const cv::Mat half = rotateEquirect(image, rotZ(kPi / width), cv::INTER_LINEAR);
  for (int v = 0; v < image.rows; ++v) {
    const double mean_across_seam = 0.5 * (image.at<float>(v, 0) + image.at<float>(v, width - 1));
    EXPECT_NEAR(half.at<float>(v, width - 1), mean_across_seam, 1e-3);
  }
}

TEST(EquirectRotation, NearestKeepsLabelsWhole) {
  const CaptureScene s = scene("lounge_furniture", 256);
  const Eigen::Quaterniond pose = s.room.rig_rotation;
  const CameraCapture camera =
      renderCaptureCamera(s.room, MaterialLibrary::loadDefault(), s.options, s.room.rig_position_m, pose);
  const cv::Mat out = rotateEquirect(camera.object_id, yawPitchRoll(25.0, 10.0, 5.0).toRotationMatrix(), cv::INTER_NEAREST);
  ASSERT_EQ(out.type(), CV_16UC1);
  const std::set<std::uint16_t> before(camera.object_id.begin<std::uint16_t>(), camera.object_id.end<std::uint16_t>());
  const std::set<std::uint16_t> after(out.begin<std::uint16_t>(), out.end<std::uint16_t>());
  for (const std::uint16_t id : after) EXPECT_TRUE(before.count(id)) << "label " << id << " is a blend";
}

TEST(EquirectRotation, BadInput) {
  const cv::Mat image(64, 128, CV_8UC3, cv::Scalar::all(90));
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  expectInputError([&] { rotateEquirect(cv::Mat(), I, cv::INTER_LINEAR); }, {"empty"});
  expectInputError([&] { rotateEquirect(cv::Mat(64, 100, CV_8UC3), I, cv::INTER_LINEAR); }, {"twice as wide", "100x64"});
  expectInputError([&] { rotateEquirect(cv::Mat(2, 4, CV_8UC1), I, cv::INTER_LINEAR); }, {"at least", "4x2"});
  expectInputError([&] { rotateEquirect(cv::Mat(64, 128, CV_64FC1), I, cv::INTER_LINEAR); }, {"8-bit"});
  expectInputError([&] { rotateEquirect(cv::Mat(64, 128, CV_8UC(5)), I, cv::INTER_LINEAR); }, {"channels"});
  Eigen::Matrix3d mirror = I;
  mirror(1, 1) = -1.0;
  expectInputError([&] { rotateEquirect(image, mirror, cv::INTER_LINEAR); }, {"not a rotation"});
  expectInputError([&] { rotateEquirect(image, 2.0 * I, cv::INTER_LINEAR); }, {"not a rotation"});
  Eigen::Matrix3d nan = I;
  nan(0, 0) = std::nan("");
  expectInputError([&] { rotateEquirect(image, nan, cv::INTER_LINEAR); }, {"not a rotation"});
  expectInputError([&] { rotateEquirect(image, I, cv::INTER_AREA); }, {"interpolation"});
}

// ---------------------------------------------------------------------------------------
// Manhattan frame from images

TEST(ManhattanFromImage, RoomAxesOfTurnedAndTiltedRigsWithinADegree) {
  struct Case {
    const char* scene;
    double yaw_deg, pitch_deg, roll_deg;
  };
  // Yaws beyond the +-45 degrees the estimate reports, tilts from a sloppy tripod to one
  // knocked over by 20 degrees; a room with furniture, an empty one, one without ceiling.
  const Case cases[] = {{"kt", 27.0, -1.5, 2.0},         {"plain_office", -38.0, 4.0, -3.0},
                        {"lounge_furniture", 63.0, 1.0, 1.0}, {"courtyard", 10.0, 0.0, 10.0},
                        {"yawed_rig_studio", -120.0, 15.0, -20.0}};
  for (const Case& c : cases) {
    const CaptureScene s = scene(c.scene, 1024);
    Eigen::Matrix3d truth;
    const cv::Mat image = renderTurned(s, yawPitchRoll(c.yaw_deg, c.pitch_deg, c.roll_deg), &truth);
    const ManhattanImageEstimate e = estimateManhattanFrame(image);
    const AngleError error = manhattanError(e.camera_to_manhattan, truth);
    std::cout << c.scene << " 1024x512: error " << error.total_deg << " deg (tilt " << error.tilt_deg << ", yaw "
              << error.yaw_deg << "), " << e.segments << " segments, " << 100.0 * e.inlier_fraction
              << " % on the axes, rms " << e.rms_residual_deg << " deg\n";
    EXPECT_LT(error.total_deg, 1.0) << c.scene;
    // Measured at most 0.2 degrees; a regression shows long before the 1 degree target.
    EXPECT_LT(error.total_deg, 0.4) << c.scene;
    // The naming: a proper rotation, z the axis nearest the camera's up, a yaw within a
    // quarter turn, tilt as the angle between the z axes.
    EXPECT_NEAR(e.camera_to_manhattan.determinant(), 1.0, 1e-9);
    EXPECT_GT(e.camera_to_manhattan(2, 2), 0.5);
    EXPECT_LE(std::abs(e.yaw_rad), kPi / 4.0 + 0.05);
    EXPECT_NEAR(e.tilt_rad, std::acos(truth(2, 2)), 0.5 * kDeg);
    EXPECT_GE(e.inlier_fraction, 0.5);
  }
}

TEST(ManhattanFromImage, BothCamerasOfTheRigPooled) {
  CaptureScene s = scene("mr", 1024);
  s.room.rig_rotation = yawPitchRoll(-22.0, 2.0, -1.0);
  const StereoCapture capture = renderCapture(s.room, MaterialLibrary::loadDefault(), s.options);
  const ManhattanImageEstimate top = estimateManhattanFrame(capture.top.color);
  const ManhattanImageEstimate both = estimateManhattanFrame(std::vector<cv::Mat>{capture.top.color, capture.bottom.color});
  const Eigen::Matrix3d truth = s.room.rig_rotation.toRotationMatrix();
  EXPECT_GT(both.segments, top.segments);
  EXPECT_LT(manhattanError(both.camera_to_manhattan, truth).total_deg, 0.4);
  // The yaw comes back as the turn about z, modulo 90 degrees: -22 here.
  EXPECT_NEAR(both.yaw_rad / kDeg, -22.0, 0.5);
}

TEST(ManhattanFromImage, ACameraTurnedOnTheBarIsTurnedBackBySegmentsNotPixels) {
  // The bottom camera stands turned 2.5 degrees against the top one; its segments, turned
  // by that rotation, give the top camera's frame as its image resampled would.
  CaptureScene s = scene("kt", 1024);
  s.room.rig_rotation = yawPitchRoll(12.0, 1.0, -0.5);
  s.options.camera.bottom_turn_deg = Eigen::Vector3d(1.5, -1.8, 0.8);
  const StereoCapture capture = renderCapture(s.room, MaterialLibrary::loadDefault(), s.options);
  const Eigen::Vector3d turn = s.options.camera.bottom_turn_deg * kDeg;
  const Eigen::Matrix3d bottom_to_top = Eigen::AngleAxisd(turn.norm(), turn.normalized()).toRotationMatrix();
  const Eigen::Matrix3d truth = capture.top.rotation.toRotationMatrix();  // top camera -> room
  const double as_it_comes = manhattanError(estimateManhattanFrame(capture.bottom.color).camera_to_manhattan, truth).total_deg;
  const double turned_back =
      manhattanError(estimateManhattanFrame(std::vector<cv::Mat>{capture.bottom.color}, {bottom_to_top}).camera_to_manhattan,
                     truth)
          .total_deg;
  const double pooled = manhattanError(estimateManhattanFrame(std::vector<cv::Mat>{capture.top.color, capture.bottom.color},
                                                              {Eigen::Matrix3d::Identity(), bottom_to_top})
                                           .camera_to_manhattan,
                                       truth)
                            .total_deg;
  std::cout << "bottom camera as it comes " << as_it_comes << " deg, turned back " << turned_back << " deg, pooled "
            << pooled << " deg\n";
  EXPECT_GT(as_it_comes, 2.0);
  EXPECT_LT(turned_back, 0.3);
  EXPECT_LT(pooled, 0.3);
}

TEST(ManhattanFromImage, KnownUpFixesZAndLeavesTheYaw) {
  const CaptureScene s = scene("yawed_rig_studio", 1024);
  Eigen::Matrix3d truth;
  const cv::Mat image = renderTurned(s, yawPitchRoll(5.0, -6.0, 3.0), &truth);
  const Eigen::Vector3d up = truth.row(2).transpose();  // the room's z in the camera frame
  ManhattanImageOptions options;
  options.known_up = up;
  const ManhattanImageEstimate e = estimateManhattanFrame(image, options);
  EXPECT_LT((e.camera_to_manhattan.row(2).transpose() - up).norm(), 1e-9);
  EXPECT_LT(manhattanError(e.camera_to_manhattan, truth).total_deg, 0.3);
}

TEST(ManhattanFromImage, SameSeedSameResult) {
  const CaptureScene s = scene("plain_office", 512);
  Eigen::Matrix3d truth;
  const cv::Mat image = renderTurned(s, yawPitchRoll(14.0, 1.0, 0.0), &truth);
  const ManhattanImageEstimate a = estimateManhattanFrame(image), b = estimateManhattanFrame(image);
  EXPECT_EQ(a.camera_to_manhattan, b.camera_to_manhattan);
  EXPECT_EQ(a.axis_inliers, b.axis_inliers);
}

TEST(ManhattanFromImage, ImagesWithoutManhattanStructure) {
  const cv::Mat black(512, 1024, CV_8UC3, cv::Scalar::all(0));
  expectInputError([&] { estimateManhattanFrame(black); }, {"no Manhattan structure", "0 straight line segments"});
  cv::Mat noise(512, 1024, CV_8UC3);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  expectInputError([&] { estimateManhattanFrame(noise); }, {"no Manhattan structure"});
  // Blurred noise: its blobs are stretched into streaks through the poles, which look like
  // vertical edges, but no second direction comes with them.
  cv::Mat blobs(1024, 2048, CV_8UC1);
  rng.fill(blobs, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(blobs, blobs, cv::Size(0, 0), 16.0);
  cv::normalize(blobs, blobs, 0, 255, cv::NORM_MINMAX);
  expectInputError([&] { estimateManhattanFrame(blobs); }, {"no Manhattan structure", "second"});
}

TEST(ManhattanFromImage, BadInput) {
  const cv::Mat grey(256, 512, CV_8UC1, cv::Scalar(80));
  expectInputError([&] { estimateManhattanFrame(cv::Mat()); }, {"empty"});
  expectInputError([&] { estimateManhattanFrame(std::vector<cv::Mat>{}); }, {"no image"});
  expectInputError([&] { estimateManhattanFrame(cv::Mat(256, 500, CV_8UC1)); }, {"twice as wide", "500x256"});
  expectInputError([&] { estimateManhattanFrame(cv::Mat(64, 128, CV_8UC1)); }, {"at least 256"});
  expectInputError([&] { estimateManhattanFrame(cv::Mat(256, 512, CV_32FC1)); }, {"8-bit"});
  ManhattanImageOptions bad;
  bad.inlier_deg = 0.0;
  expectInputError([&] { estimateManhattanFrame(grey, bad); }, {"options"});
  bad = {};
  bad.max_view_size_px = 10;
  expectInputError([&] { estimateManhattanFrame(grey, bad); }, {"options", "max_view_size_px"});
  bad = {};
  bad.known_up = Eigen::Vector3d(0.0, 0.0, 2.0);
  expectInputError([&] { estimateManhattanFrame(grey, bad); }, {"known_up"});
  const std::vector<cv::Mat> two{grey, grey};
  expectInputError([&] { estimateManhattanFrame(two, {Eigen::Matrix3d::Identity()}); }, {"one rotation per image"});
  expectInputError([&] { estimateManhattanFrame(two, {Eigen::Matrix3d::Identity(), 2.0 * Eigen::Matrix3d::Identity()}); },
                   {"not a rotation"});
}

// ---------------------------------------------------------------------------------------
// The yaw / tilt split and the IMU

TEST(ImageLeveling, SplitIsATurnAboutTheBaselineAndAHorizontalTilt) {
  for (const Eigen::Quaterniond& q : {yawPitchRoll(30.0, 3.0, -2.0), yawPitchRoll(-170.0, 40.0, 25.0),
                                      yawPitchRoll(0.0, 0.0, 0.0), yawPitchRoll(90.0, -80.0, 0.0)}) {
    const Eigen::Matrix3d R = q.toRotationMatrix();
    const ImageLeveling split = splitLeveling(R);
    EXPECT_LT((split.cameraToLevel() - R).norm(), 1e-12);
    // The images' rotation keeps the baseline (z) on the pole, so the stereo still works.
    EXPECT_LT((split.image_rotation * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
    EXPECT_LT((split.image_rotation - rotZ(split.yaw_rad)).norm(), 1e-12);
    // The tilt turns about a horizontal axis by the angle between z and the level z.
    const Eigen::AngleAxisd tilt(split.tilt);
    if (tilt.angle() > 1e-9) {
      EXPECT_NEAR(tilt.axis().z(), 0.0, 1e-9);
    }
    EXPECT_NEAR(tilt.angle(), split.tilt_rad, 1e-9);
    EXPECT_NEAR(split.tilt_rad, std::acos(R(2, 2)), 1e-9);
  }
  // A rig that is only turned has no tilt.
  const ImageLeveling turned = splitLeveling(rotZ(0.7));
  EXPECT_NEAR(turned.yaw_rad, 0.7, 1e-12);
  EXPECT_LT((turned.tilt - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
  mirror(2, 2) = -1.0;
  expectInputError([&] { splitLeveling(mirror); }, {"not a rotation"});
}

TEST(ImageLeveling, ImagesTurnedByTheYawShowTheRoomAxesUpToTheTilt) {
  // The capture_ingest path: estimate, turn the image by the yaw only, estimate again: the
  // room's axes are now the image's, but for the tilt that is left to the cloud.
  const CaptureScene s = scene("kt", 1024);
  Eigen::Matrix3d truth;
  const cv::Mat image = renderTurned(s, yawPitchRoll(31.0, 2.0, -2.5), &truth);
  const ImageLeveling leveling = splitLeveling(estimateManhattanFrame(image).camera_to_manhattan);
  const cv::Mat aligned = rotateEquirect(image, leveling.image_rotation, cv::INTER_LINEAR);
  const ManhattanImageEstimate again = estimateManhattanFrame(aligned);
  EXPECT_NEAR(again.yaw_rad / kDeg, 0.0, 0.3);
  EXPECT_NEAR(again.tilt_rad, leveling.tilt_rad, 0.3 * kDeg);
  EXPECT_LT(Eigen::AngleAxisd(again.camera_to_manhattan * leveling.tilt.transpose()).angle() / kDeg, 0.3);
}

TEST(ImageLeveling, ImuGivesTheTiltAndNoYaw) {
  // An IMU on a camera tilted by 4 and 3 degrees, with some heading to magnetic north.
  const Eigen::Quaterniond camera_to_world = yawPitchRoll(75.0, 4.0, -3.0);
  const Eigen::Vector3d up = cameraUpFromImu(camera_to_world);
  EXPECT_LT((camera_to_world * up - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  const ImageLeveling leveling = levelingFromImu(camera_to_world);
  EXPECT_LT((leveling.cameraToLevel() * up - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_LT((leveling.image_rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(leveling.tilt_rad, std::acos(camera_to_world.toRotationMatrix()(2, 2)), 1e-12);
  // Slightly off unit length is normalised; far off is an error.
  EXPECT_LT((cameraUpFromImu(Eigen::Quaterniond(camera_to_world.coeffs() * 1.0005)) - up).norm(), 1e-12);
  expectInputError([&] { cameraUpFromImu(Eigen::Quaterniond(2.0, 0.0, 0.0, 0.0)); }, {"unit quaternion"});
  expectInputError([&] { cameraUpFromImu(Eigen::Quaterniond(std::nan(""), 0.0, 0.0, 0.0)); }, {"unit quaternion"});
}
