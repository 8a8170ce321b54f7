// Dual-fisheye to equirectangular stitching with a smooth blend across the overlap.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "room_reverb/common/parallel_rows.h"
#include "room_reverb/common/error.h"
#include "room_reverb/vision/dual_fisheye.h"
#include "room_reverb/vision/equirect.h"

namespace room_reverb::core {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct LensMaps {
  cv::Mat x, y;    // CV_32FC1 remap coordinates in the lens's half (OpenCV: pixel centres at integers)
  cv::Mat weight;  // CV_32FC1 blend weight before normalisation
};

// Where each equirect pixel lands in one lens, and how much that lens counts there: full
// weight inside the part of its circle that no other lens sees, falling with a smoothstep
// across the overlap to zero at the circle's edge.
LensMaps lensMaps(const EquirectGeometry& g, const FisheyeLens& lens, FisheyeSide side, double overlap_rad) {
  LensMaps maps{cv::Mat(g.height, g.width, CV_32FC1), cv::Mat(g.height, g.width, CV_32FC1),
                cv::Mat(g.height, g.width, CV_32FC1)};
  const Eigen::Matrix3d camera_to_lens = fisheyeLensToCamera(lens, side).transpose();
  const double half_fov = 0.5 * lens.fov_deg * kDeg;
  forEachRow(g.height, 0, [&](int row) {
    float* mx = maps.x.ptr<float>(row);
    float* my = maps.y.ptr<float>(row);
    float* w = maps.weight.ptr<float>(row);
    for (int col = 0; col < g.width; ++col) {
      const Eigen::Vector3d d = camera_to_lens * equirectPixelDirection(g, col, row);
      const double sideways = std::hypot(d.x(), d.y());
      const double angle = std::atan2(sideways, d.z());
      const double margin = std::clamp((half_fov - angle) / overlap_rad, 0.0, 1.0);
      w[col] = static_cast<float>(margin * margin * (3.0 - 2.0 * margin));
      if (margin <= 0.0) {
        mx[col] = my[col] = -1.0f;
        continue;
      }
      const double r = lens.radius_px * angle / half_fov;
      const double ux = sideways > 0.0 ? d.x() / sideways : 0.0, uy = sideways > 0.0 ? d.y() / sideways : 0.0;
      // Continuous coordinates (centre of pixel i at i + 0.5) to OpenCV's (centre at i).
      mx[col] = static_cast<float>(lens.center_px.x() + r * ux - 0.5);
      my[col] = static_cast<float>(lens.center_px.y() + r * uy - 0.5);
    }
  });
  return maps;
}

}  // namespace

cv::Mat fisheyeToEquirect(const cv::Mat& dual_image, const DualFisheyeCalibration& calibration, int width) {
  if (dual_image.empty() || dual_image.cols != 2 * dual_image.rows) {
    throw InputError("dual-fisheye image is " + std::to_string(dual_image.cols) + " x " + std::to_string(dual_image.rows) +
                     ": expected 2S x S (two square lens images side by side)");
  }
  if (width < 64 || width % 2 != 0) {
    throw InputError("equirect width " + std::to_string(width) + ": must be even and at least 64 (the height is width / 2)");
  }
  validateDualFisheyeCalibration(calibration, "dual-fisheye calibration");
  const int size = dual_image.rows;
  const DualFisheyeCalibration lenses = calibration.size_px == size ? calibration : scaledDualFisheye(calibration, size);
  // The band both lenses see: for two 190° lenses, 5° either side of the plane between them.
  const double overlap = std::max((0.5 * (lenses.front.fov_deg + lenses.back.fov_deg) - 180.0) * kDeg, 1e-3);

  const EquirectGeometry g{width, width / 2};
  cv::Mat blended(g.height, g.width, CV_MAKETYPE(CV_32F, dual_image.channels()), cv::Scalar::all(0));
  cv::Mat weight_sum(g.height, g.width, CV_32FC1, cv::Scalar(0));
  for (const FisheyeSide side : {FisheyeSide::kFront, FisheyeSide::kBack}) {
    const LensMaps maps = lensMaps(g, lenses.lens(side), side, overlap);
    const cv::Mat half = dual_image(cv::Rect(side == FisheyeSide::kFront ? 0 : size, 0, size, size));
    cv::Mat sampled;
    cv::remap(half, sampled, maps.x, maps.y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    sampled.convertTo(sampled, CV_MAKETYPE(CV_32F, dual_image.channels()));
    cv::Mat weight;
    std::vector<cv::Mat> repeated(static_cast<std::size_t>(dual_image.channels()), maps.weight);
    cv::merge(repeated, weight);
    blended += sampled.mul(weight);
    weight_sum += maps.weight;
  }
  std::vector<cv::Mat> repeated(static_cast<std::size_t>(dual_image.channels()), cv::max(weight_sum, 1e-12f));
  cv::Mat denominator;
  cv::merge(repeated, denominator);
  cv::Mat out;
  cv::divide(blended, denominator, blended);
  blended.convertTo(out, dual_image.depth());
  return out;
}

}  // namespace room_reverb::core
