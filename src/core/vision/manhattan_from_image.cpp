// The Manhattan frame of equirectangular images: segments, vanishing directions, naming,
// and the checks that the structure found is real.
#include "room_reverb/vision/manhattan_from_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/vision/image_leveling.h"
#include "rotation_check.h"
#include "sphere_line_segments.h"
#include "vanishing_directions.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr int kMinWidthPx = 256;

void validateOptions(const ManhattanImageOptions& o) {
  if (!(o.view_fov_deg > 90.0 && o.view_fov_deg < 150.0) || o.view_size_px < 0 || o.max_view_size_px < 0 ||
      (o.max_view_size_px > 0 && o.max_view_size_px < 64) || !(o.min_segment_deg > 0.0) ||
      !(o.inlier_deg > 0.0 && o.inlier_deg < 10.0) || o.ransac_iterations < 1 || o.min_segments < 3 ||
      !(o.min_inlier_fraction >= 0.0 && o.min_inlier_fraction <= 1.0) ||
      !(o.min_second_axis_fraction >= 0.0 && o.min_second_axis_fraction <= 0.5) || o.min_axis_segments < 0) {
    throw InputError("Manhattan frame: options out of range (need 90 < view_fov_deg < 150, view_size_px >= 0, "
                     "max_view_size_px 0 or >= 64, "
                     "min_segment_deg > 0, 0 < inlier_deg < 10, ransac_iterations >= 1, min_segments >= 3, "
                     "min_inlier_fraction in [0, 1], min_second_axis_fraction in [0, 0.5], min_axis_segments >= 0)");
  }
  if (o.known_up && (!o.known_up->allFinite() || std::abs(o.known_up->norm() - 1.0) > 1e-3)) {
    throw InputError("Manhattan frame: known_up must be a unit vector");
  }
}

cv::Mat greyEquirect(const cv::Mat& image) {
  if (image.empty()) throw InputError("Manhattan frame: the image is empty");
  if (image.type() != CV_8UC1 && image.type() != CV_8UC3) {
    throw InputError("Manhattan frame: the image must be 8-bit grey or BGR");
  }
  if (image.cols != 2 * image.rows || image.cols < kMinWidthPx) {
    std::ostringstream os;
    os << "Manhattan frame: an equirectangular image is twice as wide as high and at least " << kMinWidthPx
       << " px wide; this one is " << image.cols << "x" << image.rows;
    throw InputError(os.str());
  }
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

// Room axes from the unordered directions: z nearest the camera's z (or the known up), x
// the nearest of the other two to the camera's x, both turned to point along them.
Eigen::Matrix3d namedAxes(const Eigen::Matrix3d& V, const std::optional<Eigen::Vector3d>& known_up) {
  int z = 2;
  if (!known_up) V.row(2).cwiseAbs().maxCoeff(&z);
  const int a = (z + 1) % 3, b = (z + 2) % 3;
  const int x = std::abs(V(0, a)) >= std::abs(V(0, b)) ? a : b;
  const Eigen::Vector3d z_axis = V(2, z) >= 0.0 || known_up ? V.col(z) : Eigen::Vector3d(-V.col(z));
  const Eigen::Vector3d x_axis = V(0, x) >= 0.0 ? V.col(x) : Eigen::Vector3d(-V.col(x));
  Eigen::Matrix3d camera_to_manhattan;
  camera_to_manhattan.row(0) = x_axis.transpose();
  camera_to_manhattan.row(1) = z_axis.cross(x_axis).transpose();
  camera_to_manhattan.row(2) = z_axis.transpose();
  return camera_to_manhattan;
}

}  // namespace

ManhattanImageEstimate estimateManhattanFrame(const std::vector<cv::Mat>& images, const ManhattanImageOptions& options) {
  return estimateManhattanFrame(images, std::vector<Eigen::Matrix3d>(images.size(), Eigen::Matrix3d::Identity()), options);
}

ManhattanImageEstimate estimateManhattanFrame(const std::vector<cv::Mat>& images,
                                              const std::vector<Eigen::Matrix3d>& rotations,
                                              const ManhattanImageOptions& options) {
  validateOptions(options);
  if (images.empty()) throw InputError("Manhattan frame: no image given");
  if (rotations.size() != images.size()) throw InputError("Manhattan frame: one rotation per image is needed");
  for (const Eigen::Matrix3d& R : rotations) vision_detail::requireRotation(R, "Manhattan frame");
  std::vector<vision_detail::SphereSegment> segments;
  // Images of one size share the views' resampling maps.
  std::vector<cv::Mat> greys;
  for (const cv::Mat& image : images) greys.push_back(greyEquirect(image));
  for (std::size_t first = 0; first < greys.size();) {
    std::size_t end = first + 1;
    while (end < greys.size() && greys[end].size() == greys[first].size()) ++end;
    // A view's centre pixel spans what an equirect pixel spans: 2 pi / W radians.
    int view_size = options.view_size_px;
    if (view_size == 0) {
      view_size = static_cast<int>(std::ceil(greys[first].cols / kPi * std::tan(0.5 * options.view_fov_deg * kDeg)));
      if (options.max_view_size_px > 0) view_size = std::min(view_size, options.max_view_size_px);
    }
    const auto found = vision_detail::detectSphereSegments(
        std::vector<cv::Mat>(greys.begin() + static_cast<std::ptrdiff_t>(first), greys.begin() + static_cast<std::ptrdiff_t>(end)),
        view_size, options.view_fov_deg * kDeg, options.min_segment_deg * kDeg);
    for (std::size_t k = 0; k < found.size(); ++k) {
      // A great circle turns with its camera: its normal by the same rotation.
      const Eigen::Matrix3d& R = rotations[first + k];
      for (vision_detail::SphereSegment segment : found[k]) {
        segment.normal = R * segment.normal;
        segments.push_back(segment);
      }
    }
    first = end;
  }
  const auto count = static_cast<int>(segments.size());
  if (count < options.min_segments) {
    throw InputError("Manhattan frame: the image shows no Manhattan structure: " + std::to_string(count) +
                     " straight line segments found, " + std::to_string(options.min_segments) +
                     " needed (is it black, blurred or noise?)");
  }

  const vision_detail::VanishingDirections fit = vision_detail::fitVanishingDirections(
      segments, options.inlier_deg * kDeg, options.ransac_iterations, options.seed, options.known_up);
  double total_length = 0.0;
  for (const auto& s : segments) total_length += s.length_rad;

  ManhattanImageEstimate out;
  out.camera_to_manhattan = namedAxes(fit.directions, options.known_up);
  const ImageLeveling split = splitLeveling(out.camera_to_manhattan);
  out.yaw_rad = split.yaw_rad;
  out.tilt_rad = split.tilt_rad;
  out.segments = count;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    // The fit's column each named axis came from.
    int column = 0;
    (fit.directions.transpose() * out.camera_to_manhattan.row(static_cast<int>(axis)).transpose()).cwiseAbs().maxCoeff(&column);
    out.axis_inliers[axis] = fit.inliers[static_cast<std::size_t>(column)];
    out.axis_fraction[axis] = fit.inlier_length_rad[static_cast<std::size_t>(column)] / total_length;
    out.inlier_fraction += out.axis_fraction[axis];
  }
  out.rms_residual_deg = fit.rms_residual_rad / kDeg;

  // The second best supported direction: sort the three by length.
  std::array<std::size_t, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return out.axis_fraction[a] > out.axis_fraction[b]; });
  const std::size_t second = order[1];
  if (out.inlier_fraction < options.min_inlier_fraction || out.axis_fraction[second] < options.min_second_axis_fraction ||
      out.axis_inliers[second] < options.min_axis_segments) {
    auto percent = [](double f) { return std::to_string(static_cast<int>(100.0 * f + 0.5)) + " %"; };
    std::ostringstream os;
    os << "Manhattan frame: the image shows no Manhattan structure: of " << count << " line segments, "
       << percent(out.inlier_fraction) << " of the length runs along three orthogonal directions ("
       << percent(options.min_inlier_fraction) << " needed), split " << percent(out.axis_fraction[order[0]]) << ", "
       << percent(out.axis_fraction[second]) << " (" << out.axis_inliers[second] << " segments), "
       << percent(out.axis_fraction[order[2]]) << " (the second needs " << percent(options.min_second_axis_fraction)
       << " and " << options.min_axis_segments << " segments)";
    throw ManhattanStructureError(os.str());
  }
  return out;
}

ManhattanImageEstimate estimateManhattanFrame(const cv::Mat& image, const ManhattanImageOptions& options) {
  return estimateManhattanFrame(std::vector<cv::Mat>{image}, options);
}

}  // namespace room_reverb::core
