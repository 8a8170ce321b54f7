// The stereo's range bias found from the room's flat floor and ceiling
// (vision/range_bias.h): the disparity offset's geometry against an independent
// triangulation, and cluttered rooms (synthetic_capture/cluttered_rooms.h) scanned as
// stereo ranges them (test/support/room_scan.h) and bent by known offsets, constant and
// with the azimuth, fitted with and without the correction; a levelling that is off. A report over many rooms and offsets:
// ROOM_REVERB_ROOMS=20 [ROOM_REVERB_FIRST_ROOM=1] [ROOM_REVERB_ROOM_SET=development]
//   .ws/devel/lib/room_reverb/test_range_bias --gtest_filter='*Report*'
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "room_reverb/synthetic_capture/cluttered_rooms.h"
#include "room_reverb/vision/range_bias.h"
#include "room_reverb/vision/room_layout.h"
#include "room_scan.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;
using room_reverb::test::RoomScanOptions;
using room_reverb::test::scanRoomModel;
using room_reverb::test::stereoLikeScanOptions;

namespace {

constexpr double kBaseline = 0.2;
// One pixel of a 2048 x 1024 equirect image [rad].
constexpr double kPixel2048 = M_PI / 1024.0;

// The scan's points as a stereo pair with its disparity offset by `offset_rad` would
// range them: each along its ray from the top camera.
PointCloud bent(const PointCloud& cloud, double offset_rad) { return removeDisparityOffset(cloud, kBaseline, -offset_rad); }

// A room scanned as stereo ranges it: the noise in each point's disparity (1-sigma
// `disparity_noise_rad`), so that the range noise grows with the square of the range, as
// it does for a matcher; 3 % strays beyond the walls, no range near the poles.
PointCloud stereoScan(const RoomModel& room, std::uint32_t seed, double disparity_noise_rad = 1e-3) {
  RoomScanOptions options = stereoLikeScanOptions(seed);
  options.range_noise_fraction = 0.0;
  PointCloud cloud = scanRoomModel(room, options).cloud;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, disparity_noise_rad);
  const Eigen::Vector3d top(0.0, 0.0, kBaseline / 2.0);
  for (CloudPoint& point : cloud.points) {
    const Eigen::Vector3d v = point.p.cast<double>() - top;
    const double range = v.norm();
    const double polar = std::acos(std::clamp(v.z() / range, -1.0, 1.0));
    const double noisy = rangeWithoutDisparityOffset(range, polar, kBaseline, gauss(rng));
    if (std::isfinite(noisy) && noisy < 30.0) point.p = (top + noisy * v / range).cast<float>();
  }
  return cloud;
}

Eigen::Matrix3d levelOf(const RoomModel& scanned) { return scanned.rig_rotation.toRotationMatrix(); }

// The largest error of the box's three sizes, as a fraction of the true size.
double worstBoxError(const RoomModel& fitted, const RoomModel& truth) {
  double worst = 0.0;
  for (int a = 0; a < 3; ++a) worst = std::max(worst, std::abs(fitted.size_m[a] - truth.size_m[a]) / truth.size_m[a]);
  return worst;
}

}  // namespace

TEST(RangeBias, TheOffsetsRangeIsATriangulationWithTheBottomRayTurned) {
  // The two cameras on the z axis, the bottom one's ray to the point turned by the offset
  // (a bottom camera that sees every point `offset` nearer its zenith reads a disparity
  // `offset` larger); the top camera's and the turned bottom ray meet at the biased point.
  const double offset = 0.004;
  for (const Eigen::Vector3d& point : {Eigen::Vector3d(3.0, 0.0, -1.4), Eigen::Vector3d(-1.2, 4.5, 1.1),
                                      Eigen::Vector3d(0.3, -0.4, -1.5), Eigen::Vector3d(6.5, 2.0, 0.0)}) {
    const Eigen::Vector3d top(0.0, 0.0, kBaseline / 2.0), bottom(0.0, 0.0, -kBaseline / 2.0);
    const double rho = std::hypot(point.x(), point.y());
    const double polar_top = std::atan2(rho, point.z() - top.z());
    const double polar_bottom = std::atan2(rho, point.z() - bottom.z()) - offset;
    // In the vertical plane through the point: top ray z = top.z + rho / tan(polar_top),
    // bottom ray z = bottom.z + rho' / tan(polar_bottom); they meet where both give one z.
    const double meet_rho = kBaseline / (1.0 / std::tan(polar_bottom) - 1.0 / std::tan(polar_top));
    const double meet_range = meet_rho / std::sin(polar_top);
    const double range = (point - top).norm();
    EXPECT_NEAR(rangeWithoutDisparityOffset(range, polar_top, kBaseline, -offset), meet_range, 1e-9 * meet_range);
    // And the correction takes the offset out again.
    EXPECT_NEAR(rangeWithoutDisparityOffset(meet_range, polar_top, kBaseline, offset), range, 1e-9 * range);
    EXPECT_NEAR(rangeWithoutDisparityOffset(range, polar_top, kBaseline, 0.0), range, 1e-12 * range);
  }
  // A disparity corrected through zero is a point at infinity.
  EXPECT_TRUE(std::isnan(rangeWithoutDisparityOffset(50.0, M_PI / 2.0, kBaseline, 0.01)));
}

TEST(RangeBias, AnOffsetThatBentTheRoomIsFoundAndTakenOut) {
  // Half a pixel and one pixel at 2048 x 1024 either way: a matcher's sub-pixel bias, a
  // camera's projection placing every elevation a twentieth of a degree off. Half a pixel
  // (1.5 mrad) is under the default threshold, which the consumer camera's own floors and
  // ceilings ask for; the estimate and the correction are those of a lower one.
  const double offsets_px[] = {0.5, 1.0, -1.0};
  DisparityOffsetOptions lower;
  lower.min_offset_rad = 1e-3;
  int index = 1;
  for (double px : offsets_px) {
    const ClutteredRoom room = clutteredRoom(ClutterSet::kDevelopment, index++);
    const PointCloud seen = bent(stereoScan(room.scanned, 5), px * kPixel2048);
    const DisparityOffset found = estimateDisparityOffset(seen, kBaseline, levelOf(room.scanned), lower);
    EXPECT_EQ(estimateDisparityOffset(seen, kBaseline, levelOf(room.scanned)).applied, std::abs(px) * kPixel2048 >= 2e-3)
        << room.name << ": the default threshold is 2 mrad";
    const double bent_error = worstBoxError(fitRoomLayout(seen).model, room.truth);
    const double corrected_error =
        worstBoxError(fitRoomLayout(removeDisparityOffset(seen, kBaseline, found.offset_rad)).model, room.truth);
    std::printf("[ measured ] %s offset %+.2f px: found %+.3f px (floor %+.3f, ceiling %+.3f)%s, box error %.2f %% "
                "bent, %.2f %% corrected\n",
                room.name.c_str(), px, found.offset_rad / kPixel2048, found.floor_offset_rad / kPixel2048,
                found.ceiling_offset_rad / kPixel2048, found.applied ? " applied" : "", 100.0 * bent_error,
                100.0 * corrected_error);
    EXPECT_TRUE(found.applied) << room.name;
    // The matcher's noise (1 mrad a point) and what stands on the floor leave about a
    // quarter of a pixel at this width; the box comes within 1.5 % from 2.5-5 %.
    EXPECT_NEAR(found.offset_rad / kPixel2048, px, 0.25) << room.name;
    EXPECT_GT(bent_error, 0.02) << room.name << ": the offset should bend the room measurably";
    EXPECT_LE(corrected_error, 0.015) << room.name;
    EXPECT_LE(corrected_error, bent_error / 2.5) << room.name;
  }
}

TEST(RangeBias, AnUnbentCloudStaysAsItIs) {
  for (int index = 4; index <= 6; ++index) {
    const ClutteredRoom room = clutteredRoom(ClutterSet::kDevelopment, index);
    const DisparityOffset found = estimateDisparityOffset(stereoScan(room.scanned, 6), kBaseline, levelOf(room.scanned));
    std::printf("[ measured ] %s unbent: found %+.3f +- %.3f px%s\n", room.name.c_str(),
                found.offset_rad / kPixel2048, found.standard_error_rad / kPixel2048, found.applied ? ", applied" : "");
    EXPECT_FALSE(found.applied) << room.name;
    EXPECT_FALSE(found.azimuth_applied) << room.name;
    EXPECT_LE(std::abs(found.offset_rad), 0.2 * kPixel2048) << room.name;
    EXPECT_LE(std::hypot(found.cos_rad, found.sin_rad), 0.2 * kPixel2048) << room.name;
  }
}

TEST(RangeBias, ARoomOpenToTheSkyHasItsFloor) {
  ClutteredRoom room = clutteredRoom(ClutterSet::kDevelopment, 7);
  room.scanned.has_ceiling = false;
  const PointCloud seen = bent(stereoScan(room.scanned, 8), 0.8 * kPixel2048);
  const DisparityOffset found = estimateDisparityOffset(seen, kBaseline, levelOf(room.scanned));
  std::printf("[ measured ] %s without a ceiling, offset +0.80 px: found %+.3f px\n", room.name.c_str(),
              found.offset_rad / kPixel2048);
  EXPECT_TRUE(found.applied);
  EXPECT_TRUE(found.floor_fitted);
  EXPECT_FALSE(found.ceiling_fitted);
  EXPECT_NEAR(found.offset_rad / kPixel2048, 0.8, 0.15);
}

TEST(RangeBias, AnOffsetThatGoesWithTheAzimuthIsFoundAndTakenOut) {
  // The bottom camera tilted against the top one by one pixel at 2048 x 1024 (3 mrad) about
  // axes of three directions, one of them with a pixel of constant offset as well.
  struct Case {
    double cos_px, sin_px, constant_px;
  };
  const Case cases[] = {{1.0, 0.0, 0.0}, {-0.5, 0.87, 0.0}, {-0.34, -0.94, 1.0}};
  int index = 1;
  for (const Case& c : cases) {
    const ClutteredRoom room = clutteredRoom(ClutterSet::kDevelopment, index++);
    DisparityOffset planted;
    planted.offset_rad = -c.constant_px * kPixel2048;
    planted.cos_rad = -c.cos_px * kPixel2048;
    planted.sin_rad = -c.sin_px * kPixel2048;
    planted.applied = planted.azimuth_applied = true;
    const PointCloud seen = removeDisparityOffset(stereoScan(room.scanned, 5), kBaseline, planted);
    const DisparityOffset found = estimateDisparityOffset(seen, kBaseline, levelOf(room.scanned));
    const double bent_error = worstBoxError(fitRoomLayout(seen).model, room.truth);
    const double corrected_error =
        worstBoxError(fitRoomLayout(removeDisparityOffset(seen, kBaseline, found)).model, room.truth);
    std::printf("[ measured ] %s offset %+.2f px + (%+.2f, %+.2f) px with the azimuth: found %+.3f + (%+.3f, %+.3f) px "
                "(+- %.3f)%s%s, plane tilt %.2f mrad; box error %.2f %% bent, %.2f %% corrected\n",
                room.name.c_str(), c.constant_px, c.cos_px, c.sin_px, found.offset_rad / kPixel2048,
                found.cos_rad / kPixel2048, found.sin_rad / kPixel2048, found.azimuth_standard_error_rad / kPixel2048,
                found.applied ? " applied" : "", found.azimuth_applied ? ", azimuth applied" : "",
                1e3 * found.plane_tilt_rad, 100.0 * bent_error, 100.0 * corrected_error);
    EXPECT_TRUE(found.azimuth_applied) << room.name;
    EXPECT_EQ(found.applied, c.constant_px != 0.0) << room.name;
    EXPECT_NEAR(found.cos_rad / kPixel2048, c.cos_px, 0.25) << room.name;
    EXPECT_NEAR(found.sin_rad / kPixel2048, c.sin_px, 0.25) << room.name;
    // Opposite walls move opposite ways: the box's sizes change less than its walls.
    EXPECT_GT(bent_error, 0.015) << room.name;
    EXPECT_LE(corrected_error, 0.015) << room.name;
  }
}

TEST(RangeBias, ALevelThatIsOffIsNotTakenForAnOffset) {
  // The levelling 3 mrad off (a sixth of a degree): the floor and the ceiling tilt alike,
  // which no disparity offset does.
  for (int index = 4; index <= 5; ++index) {
    const ClutteredRoom room = clutteredRoom(ClutterSet::kDevelopment, index);
    const Eigen::Matrix3d off_level =
        Eigen::AngleAxisd(0.003, Eigen::Vector3d(0.6, 0.8, 0.0)).toRotationMatrix() * levelOf(room.scanned);
    const DisparityOffset found = estimateDisparityOffset(stereoScan(room.scanned, 6), kBaseline, off_level);
    std::printf("[ measured ] %s levelled 3 mrad off: found %+.3f + (%+.3f, %+.3f) px, plane tilt %.2f mrad%s%s\n",
                room.name.c_str(), found.offset_rad / kPixel2048, found.cos_rad / kPixel2048,
                found.sin_rad / kPixel2048, 1e3 * found.plane_tilt_rad, found.applied ? ", applied" : "",
                found.azimuth_applied ? ", azimuth applied" : "");
    EXPECT_FALSE(found.applied) << room.name;
    EXPECT_FALSE(found.azimuth_applied) << room.name;
    EXPECT_NEAR(found.plane_tilt_rad, 0.003, 0.001) << room.name;
  }
}

TEST(RangeBias, BadInput) {
  const ClutteredRoom room = clutteredRoom(ClutterSet::kDevelopment, 1);
  const PointCloud scan = scanRoomModel(room.scanned, stereoLikeScanOptions(2)).cloud;
  const Eigen::Matrix3d level = levelOf(room.scanned);
  expectInputError([&] { estimateDisparityOffset(scan, 0.0, level); }, {"baseline"});
  expectInputError([&] { estimateDisparityOffset(scan, std::nan(""), level); }, {"baseline"});
  DisparityOffsetOptions wide;
  wide.max_offset_rad = 0.5;
  expectInputError([&] { estimateDisparityOffset(scan, kBaseline, level, wide); }, {"max_offset_rad"});
  PointCloud few;
  few.points.resize(10);
  expectInputError([&] { estimateDisparityOffset(few, kBaseline, level); }, {"too few points"});
  PointCloud broken = scan;
  broken.points[5].p.x() = std::nanf("");
  expectInputError([&] { estimateDisparityOffset(broken, kBaseline, level); }, {"not finite"});
}

TEST(RangeBiasReport, Summary) {
  const char* rooms_env = std::getenv("ROOM_REVERB_ROOMS");
  const int rooms = rooms_env != nullptr ? std::atoi(rooms_env) : 0;
  if (rooms < 1) GTEST_SKIP() << "set ROOM_REVERB_ROOMS=N for the report over N rooms";
  const char* first_env = std::getenv("ROOM_REVERB_FIRST_ROOM");
  const int first = first_env != nullptr ? std::atoi(first_env) : 1;
  const char* set_env = std::getenv("ROOM_REVERB_ROOM_SET");
  const bool development = set_env != nullptr && std::string(set_env) == "development";
  const double offsets_px[] = {0.0, 0.5, 1.0, -0.5, 1.5};
  for (double px : offsets_px) {
    std::vector<double> found_error, bent_error, corrected_error;
    int applied = 0, within_bent = 0, within_corrected = 0;
    for (int index = first; index < first + rooms; ++index) {
      const ClutteredRoom room = clutteredRoom(development ? ClutterSet::kDevelopment : ClutterSet::kHeldOut, index);
      const PointCloud seen = bent(stereoScan(room.scanned, 9), px * kPixel2048);
      const DisparityOffset found = estimateDisparityOffset(seen, kBaseline, levelOf(room.scanned));
      applied += found.applied ? 1 : 0;
      found_error.push_back(std::abs(found.offset_rad / kPixel2048 - px));
      const double before = worstBoxError(fitRoomLayout(seen).model, room.truth);
      const PointCloud used = found.applied ? removeDisparityOffset(seen, kBaseline, found.offset_rad) : seen;
      const double after = worstBoxError(fitRoomLayout(used).model, room.truth);
      bent_error.push_back(before), corrected_error.push_back(after);
      within_bent += before <= 0.01 ? 1 : 0, within_corrected += after <= 0.01 ? 1 : 0;
      std::printf("[ measured ] %-20s offset %+.2f px: found %+.3f +- %.3f px%s, box %.2f %% -> %.2f %%\n",
                  room.name.c_str(), px, found.offset_rad / kPixel2048, found.standard_error_rad / kPixel2048,
                  found.applied ? " applied" : "", 100.0 * before, 100.0 * after);
    }
    const auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    std::printf("[ measured ] offset %+.2f px (2048 px wide): applied in %d of %d; offset error median %.3f px, max "
                "%.3f px; box within 1 %%: %d bent -> %d corrected; worst dimension median %.2f %% -> %.2f %%, max "
                "%.2f %% -> %.2f %%\n",
                px, applied, rooms, median(found_error), *std::max_element(found_error.begin(), found_error.end()),
                within_bent, within_corrected, 100.0 * median(bent_error), 100.0 * median(corrected_error),
                100.0 * *std::max_element(bent_error.begin(), bent_error.end()),
                100.0 * *std::max_element(corrected_error.begin(), corrected_error.end()));
  }
}
