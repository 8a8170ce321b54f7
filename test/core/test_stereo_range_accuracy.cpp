// The spherical stereo's range accuracy with distance (vision/spherical_stereo.h), at the
// size the visual route's targets are set for (2048 x 1024, 0.2 m vertical baseline), on
// generated pairs with sensor noise: a hall whose walls stand 3.8 to 6.2 m from the rig,
// and a second hall that no option was chosen on (other sizes, finishes, rig position and
// seed). A vertical baseline's disparity is b sin(theta) / r: about 8 pixels at 8 m on
// the horizon, so a tenth of a pixel is over 1 % of the range there, and a plain wall
// (smooth plaster, concrete) gives a 7 x 7 window too little texture to be matched to
// better than that; the plane fitted to a whole tile's grey levels
// (vision/planar_disparity.h) is. The bounds (default options) are on walls seen within 45
// degrees of face-on (docs/visual-route.md has the figures). Everything else (the floor
// and ceiling, seen near the poles where a vertical baseline has no disparity, and walls
// seen along their length) is reported.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/vision/spherical_stereo.h"

using namespace room_reverb::core;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A box room without objects; `finishes` in the order of kRoomSurfaceNames.
RoomModel hall(const Eigen::Vector3d& size_m, const std::array<const char*, 6>& finishes, const Eigen::Vector3d& rig_m) {
  RoomModel room;
  room.size_m = size_m;
  for (std::size_t k = 0; k < finishes.size(); ++k) room.surfaces[kRoomSurfaceNames[k]] = {finishes[k], 1.0};
  room.rig_position_m = rig_m;
  return room;
}

double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

// Median range errors on the walls face-on, per band of true range, with the default
// options, without the planes and without any sub-pixel step; printed per band.
struct BandErrors {
  std::vector<double> edges = {1.0, 2.0, 3.0, 5.0, 8.0, 9.5};
  std::vector<double> median, without_planes, unrefined, valid;
  std::vector<std::size_t> count;
};

BandErrors measureBands(const RoomModel& room, std::uint32_t seed) {
  CaptureOptions options;
  options.width = 2048;
  options.supersampling = 2;
  options.noise_sigma = 2.0;
  options.seed = seed;
  const StereoCapture pair = renderCapture(room, MaterialLibrary::loadDefault(), options);
  const SphericalStereoOptions stereo;
  SphericalStereoOptions no_planes;
  no_planes.planar_refinement = false;
  SphericalStereoOptions whole;
  whole.subpixel_refinement = false;
  const SphericalDepth depths[3] = {
      computeSphericalDepth(pair.top.color, pair.bottom.color, options.baseline_m, stereo),
      computeSphericalDepth(pair.top.color, pair.bottom.color, options.baseline_m, no_planes),
      computeSphericalDepth(pair.top.color, pair.bottom.color, options.baseline_m, whole)};

  BandErrors out;
  const std::size_t bands = out.edges.size() - 1;
  std::vector<std::vector<double>> errors[3], grazing(bands);
  for (auto& e : errors) e.resize(bands);
  std::vector<long> seen(bands, 0);
  const Eigen::Vector3d normals[6] = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                                      Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitY()};
  const cv::Mat& truth = pair.top.range_m;
  const double cap = stereo.polar_cap_deg * kPi / 180.0;
  for (int v = 0; v < truth.rows; ++v) {
    const double theta = (v + 0.5) * kPi / truth.rows;
    if (theta < cap || theta > kPi - cap) continue;
    for (int u = 0; u < truth.cols; ++u) {
      const double r = truth.at<float>(v, u);
      const int face = pair.top.object_id.at<std::uint16_t>(v, u);
      if (face >= 6) continue;
      const double phi = kPi - (u + 0.5) * 2.0 * kPi / truth.cols;
      const Eigen::Vector3d ray(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const bool face_on = face >= 2 && std::abs(ray.dot(normals[face])) >= std::cos(45.0 * kPi / 180.0);
      const auto band = std::upper_bound(out.edges.begin(), out.edges.end(), r) - out.edges.begin() - 1;
      if (band < 0 || band >= static_cast<std::ptrdiff_t>(bands)) continue;
      const auto b = static_cast<std::size_t>(band);
      if (face_on) ++seen[b];
      for (int k = 0; k < 3; ++k) {
        if (!depths[k].valid.at<std::uint8_t>(v, u)) continue;
        const double error = std::abs(depths[k].range_m.at<float>(v, u) - r) / r;
        if (face_on) {
          errors[k][b].push_back(error);
        } else if (k == 0) {
          grazing[b].push_back(error);
        }
      }
    }
  }
  for (std::size_t b = 0; b < bands; ++b) {
    out.median.push_back(median(errors[0][b]));
    out.without_planes.push_back(median(errors[1][b]));
    out.unrefined.push_back(median(errors[2][b]));
    out.count.push_back(errors[0][b].size());
    out.valid.push_back(static_cast<double>(errors[0][b].size()) / static_cast<double>(std::max(seen[b], 1L)));
    std::printf("[ measured ] range %4.1f-%4.1f m: walls face-on: median error %.2f %% (without the planes %.2f %%, "
                "unrefined %.2f %%; valid %.0f %% of %ld pixels); the rest %.2f %% (%zu pixels)\n",
                out.edges[b], out.edges[b + 1], 100.0 * out.median[b], 100.0 * out.without_planes[b],
                100.0 * out.unrefined[b], 100.0 * out.valid[b], seen[b], 100.0 * median(grazing[b]), grazing[b].size());
  }
  return out;
}

// Each sub-pixel step is never worse than the one before it on walls, the median error is
// under `near` at 3-5 m and under `far` at 5-8 m, and `ranged` of the walls are ranged.
void expectBands(const BandErrors& e, double near, double far, double ranged) {
  for (std::size_t b = 0; b < e.median.size(); ++b) {
    if (e.count[b] < 500) continue;  // no wall face-on at this range
    const std::string band = std::to_string(e.edges[b]) + "-" + std::to_string(e.edges[b + 1]) + " m";
    EXPECT_LE(e.without_planes[b], e.unrefined[b]) << "the window's step against the matcher's, " << band;
    if (e.edges[b + 1] <= 8.0) {
      EXPECT_LE(e.median[b], e.without_planes[b]) << "the planes against the window, " << band;
    }
    if (e.edges[b + 1] <= 5.0) {
      EXPECT_LT(e.median[b], near) << band;
    } else if (e.edges[b + 1] <= 8.0) {
      EXPECT_LT(e.median[b], far) << band;
    }
    EXPECT_GT(e.valid[b], ranged) << band;
  }
}

}  // namespace

TEST(StereoRangeAccuracy, MedianErrorOnWallsFromOneToEightMetres) {
  // Measured: 0.10 % at 3-5 m and 0.55 % at 5-8 m (without the planes 0.54 and 1.39 %);
  // 100 % and 88 % of those walls ranged, the rest too plain for the noise
  // (SphericalStereoOptions::min_texture_snr).
  const RoomModel room = hall({10.0, 12.0, 3.2},
                              {"wood_floor", "acoustic_ceiling_tiles", "brick_bare", "plaster_rough",
                               "concrete_unpainted", "plaster_smooth"},
                              {3.8, 6.0, 1.5});
  expectBands(measureBands(room, 11), 0.004, 0.01, 0.85);
}

// Held out: every finish of the first hall moved to another wall or replaced, another
// size and rig position, another seed; no option was chosen on it. Measured:
// 0.47 % at 5-8 m (1.19 % without the planes, 95 % ranged) and 0.85 % at 3-5 m (1.20 %),
// where the only wall face-on is unpainted concrete 4.1 m away. The generated concrete's
// finest detail is near the pixel's size, and the two views' samples of it differ: on the
// first hall's concrete without sensor noise the grey levels' least-squares minimum lies
// 0.12 px from the true plane, and that wall stays at 1.9 %. Half of it (49 %) is ranged:
// the other half's slopes along the epipolar line are within a quarter of what the noise
// alone gives them (SphericalStereoOptions::min_texture_snr); kept, they put the wall's
// median at 1.58 %.
TEST(StereoRangeAccuracy, HeldOutHallWithinOnePercentFromFiveToEightMetres) {
  const RoomModel room = hall({9.0, 13.0, 3.0},
                              {"carpet_on_concrete", "plaster_smooth", "concrete_unpainted", "plaster_smooth",
                               "plaster_rough", "wood_panel"},
                              {4.1, 6.8, 1.4});
  expectBands(measureBands(room, 29), 0.02, 0.01, 0.4);
}
