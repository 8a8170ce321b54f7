// The spherical stereo's range accuracy with distance (vision/spherical_stereo.h), at the
// size the visual route's targets are set for (2048 x 1024, 0.2 m vertical baseline), on
// generated pairs with sensor noise: a hall whose walls stand 3.8 to 6.2 m from the rig.
// A vertical baseline's disparity is b sin(theta) / r: about 8 pixels at 8 m on the
// horizon, so a tenth of a pixel is over 1 % of the range there, and a plain wall (smooth
// plaster) is matched to about that. The bounds (default options) are on walls seen
// within 45 degrees of face-on (docs/visual-route.md has the figures). Everything else
// (the floor and ceiling, seen near the poles where a vertical baseline has no
// disparity, and walls seen along their length) is reported.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/vision/spherical_stereo.h"

using namespace room_reverb::core;

namespace {

constexpr double kPi = 3.14159265358979323846;

RoomModel hall() {
  RoomModel room;
  room.size_m = {10.0, 12.0, 3.2};
  room.surfaces["floor"] = {"wood_floor", 1.0};
  room.surfaces["ceiling"] = {"acoustic_ceiling_tiles", 1.0};
  room.surfaces["wall_x_min"] = {"brick_bare", 1.0};
  room.surfaces["wall_x_max"] = {"plaster_rough", 1.0};
  room.surfaces["wall_y_min"] = {"concrete_unpainted", 1.0};
  room.surfaces["wall_y_max"] = {"plaster_smooth", 1.0};
  room.rig_position_m = {3.8, 6.0, 1.5};
  return room;
}

double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

}  // namespace

TEST(StereoRangeAccuracy, MedianErrorOnWallsFromOneToEightMetres) {
  CaptureOptions options;
  options.width = 2048;
  options.supersampling = 2;
  options.noise_sigma = 2.0;
  options.seed = 11;
  const StereoCapture pair = renderCapture(hall(), MaterialLibrary::loadDefault(), options);
  const SphericalStereoOptions stereo;
  const SphericalDepth depth = computeSphericalDepth(pair.top.color, pair.bottom.color, options.baseline_m, stereo);

  // Bands of true range [m]; errors only where the stereo gives a measurement.
  const std::vector<double> edges = {1.0, 2.0, 3.0, 5.0, 8.0, 9.5};
  std::vector<std::vector<double>> errors(edges.size() - 1), grazing(edges.size() - 1), unrefined(edges.size() - 1);
  std::vector<long> seen(edges.size() - 1, 0);
  // The same pair without the sub-pixel refinement (on by default): the matcher's own
  // sub-pixel step.
  SphericalStereoOptions whole;
  whole.subpixel_refinement = false;
  const SphericalDepth unrefined_depth = computeSphericalDepth(pair.top.color, pair.bottom.color, options.baseline_m, whole);
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
      const auto band = std::upper_bound(edges.begin(), edges.end(), r) - edges.begin() - 1;
      if (band < 0 || band >= static_cast<std::ptrdiff_t>(errors.size())) continue;
      if (face_on) ++seen[static_cast<std::size_t>(band)];
      if (!depth.valid.at<std::uint8_t>(v, u)) continue;
      (face_on ? errors : grazing)[static_cast<std::size_t>(band)].push_back(std::abs(depth.range_m.at<float>(v, u) - r) / r);
      if (face_on && unrefined_depth.valid.at<std::uint8_t>(v, u)) {
        unrefined[static_cast<std::size_t>(band)].push_back(std::abs(unrefined_depth.range_m.at<float>(v, u) - r) / r);
      }
    }
  }
  for (std::size_t b = 0; b < errors.size(); ++b) {
    const double m = median(errors[b]);
    const double valid = static_cast<double>(errors[b].size()) / static_cast<double>(std::max(seen[b], 1L));
    std::printf("[ measured ] range %4.1f-%4.1f m: walls face-on: median error %.2f %% (unrefined %.2f %%; valid %.0f %% of %ld "
                "pixels); the rest %.2f %% (%zu pixels)\n",
                edges[b], edges[b + 1], 100.0 * m, 100.0 * median(unrefined[b]), 100.0 * valid, seen[b],
                100.0 * median(grazing[b]), grazing[b].size());
    if (errors[b].size() < 500) continue;  // no wall face-on at this range
    // The refinement moves each disparity to the window's least-squares minimum: on walls
    // it is never worse than the matcher's own sub-pixel step.
    EXPECT_LE(m, median(unrefined[b])) << "refined against unrefined, range " << edges[b] << "-" << edges[b + 1] << " m";
    if (edges[b + 1] <= 5.0) {
      EXPECT_LT(m, 0.01) << "range " << edges[b] << "-" << edges[b + 1] << " m";
    } else if (edges[b + 1] <= 8.0) {
      EXPECT_LT(m, 0.02) << "range " << edges[b] << "-" << edges[b + 1] << " m";
    }
    EXPECT_GT(valid, 0.9) << "range " << edges[b] << "-" << edges[b + 1] << " m";
  }
}
