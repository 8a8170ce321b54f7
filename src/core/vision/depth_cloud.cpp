#include "room_reverb/vision/depth_cloud.h"

#include <cmath>
#include <vector>

#include <opencv2/core.hpp>

#include "room_reverb/common/error.h"
#include "room_reverb/vision/equirect.h"

namespace room_reverb::core {

PointCloud depthToPointCloud(const SphericalDepth& depth, const cv::Mat& top_color, double baseline_m,
                             const DepthCloudOptions& options, const cv::Mat& hints) {
  if (depth.range_m.empty() || depth.range_m.type() != CV_32FC1 || depth.valid.size() != depth.range_m.size()) {
    throw InputError("depth cloud: the depth image is empty or malformed");
  }
  if (top_color.size() != depth.range_m.size()) throw InputError("depth cloud: the colour image and the depth differ in size");
  if (top_color.type() != CV_8UC3 && top_color.type() != CV_8UC1) throw InputError("depth cloud: colour must be 8-bit BGR or grey");
  if (!hints.empty() && (hints.size() != depth.range_m.size() || hints.type() != CV_16UC1)) {
    throw InputError("depth cloud: the hint image must be CV_16UC1 of the depth's size");
  }
  if (!(baseline_m > 0.0) || !std::isfinite(baseline_m)) throw InputError("depth cloud: the baseline must be positive");
  if (options.stride < 1) throw InputError("depth cloud: stride must be at least 1");

  const EquirectGeometry g{depth.range_m.cols, depth.range_m.rows};
  const Eigen::Vector3d camera(0.0, 0.0, baseline_m / 2.0);
  PointCloud cloud;
  cloud.frame = "rig";
  cloud.has_color = true;
  // Per column and row instead of per pixel: a third of the conversion's time at 2048 x 1024.
  const EquirectDirections directions = equirectDirections(g);
  if (options.stride == 1) cloud.points.reserve(static_cast<std::size_t>(cv::countNonZero(depth.valid)));
  for (int v = 0; v < g.height; v += options.stride) {
    for (int u = 0; u < g.width; u += options.stride) {
      if (depth.valid.at<std::uint8_t>(v, u) == 0) continue;
      if (!options.include_filled && !depth.filled.empty() && depth.filled.at<std::uint8_t>(v, u) != 0) continue;
      const float range = depth.range_m.at<float>(v, u);
      if (!std::isfinite(range)) continue;
      CloudPoint point;
      const Eigen::Vector3d direction = directions.at(u, v);
      point.p = (camera + static_cast<double>(range) * direction).cast<float>();
      if (top_color.channels() == 3) {
        const cv::Vec3b bgr = top_color.at<cv::Vec3b>(v, u);
        point.b = bgr[0];
        point.g = bgr[1];
        point.r = bgr[2];
      } else {
        point.r = point.g = point.b = top_color.at<std::uint8_t>(v, u);
      }
      if (!hints.empty()) point.hint = hints.at<std::uint16_t>(v, u);
      cloud.points.push_back(point);
    }
  }
  return cloud;
}

SphericalDepth depthFromRangeImage(const cv::Mat& range_m, const cv::Size& top_size, const std::string& what) {
  if (range_m.type() != CV_32FC1) {
    throw InputError(what + ": a range image must be one channel of 32-bit float metres (as room-model --range writes)");
  }
  if (range_m.size() != top_size) {
    throw InputError(what + ": the range image is " + std::to_string(range_m.cols) + "x" + std::to_string(range_m.rows) +
                     ", the top image " + std::to_string(top_size.width) + "x" + std::to_string(top_size.height) +
                     " (it must be on the top image's grid)");
  }
  SphericalDepth depth;
  depth.range_m = range_m.clone();
  depth.valid = cv::Mat(range_m.size(), CV_8UC1, cv::Scalar(0));
  depth.filled = cv::Mat(range_m.size(), CV_8UC1, cv::Scalar(0));
  int valid = 0;
  for (int r = 0; r < range_m.rows; ++r) {
    float* row = depth.range_m.ptr<float>(r);
    std::uint8_t* ok = depth.valid.ptr<std::uint8_t>(r);
    for (int c = 0; c < range_m.cols; ++c) {
      if (std::isfinite(row[c]) && row[c] > 0.0f) {
        ok[c] = 255;
        ++valid;
      } else {
        row[c] = std::nanf("");
      }
    }
  }
  if (valid == 0) throw InputError(what + ": the range image has no valid (finite, positive) range");
  return depth;
}

}  // namespace room_reverb::core
