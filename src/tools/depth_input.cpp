#include "depth_input.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <pcl/console/print.h>
#include <pcl/conversions.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include "image_files.h"
#include "room_reverb/common/error.h"
#include "room_reverb/vision/depth_cloud.h"
#include "room_reverb/vision/equirect_rotation.h"

namespace room_reverb::tool {
namespace {

using core::InputError;

std::string extensionOf(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

core::PointCloud cloudFromRange(const std::string& path, const cv::Mat& top, double baseline_m,
                                const Eigen::Matrix3d& image_rotation) {
  core::SphericalDepth depth = core::depthFromRangeImage(readImage(path), top.size(), path);
  // Turned about the baseline as the top image was; nearest neighbour, so that no range is
  // invented across a depth edge.
  depth.range_m = core::rotateEquirect(depth.range_m, image_rotation, cv::INTER_NEAREST);
  depth.valid = core::rotateEquirect(depth.valid, image_rotation, cv::INTER_NEAREST);
  depth.filled = core::rotateEquirect(depth.filled, image_rotation, cv::INTER_NEAREST);
  return core::depthToPointCloud(depth, top, baseline_m);
}

core::PointCloud cloudFromPcd(const std::string& path, const Eigen::Matrix3d& image_rotation) {
  pcl::PCLPointCloud2 blob;
  pcl::PointCloud<pcl::PointXYZRGB> points;
  bool has_rgb = false, has_xyz[3] = {false, false, false};
  // PCL prints its own diagnostics on stderr; the tool says what went wrong in one line.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  try {
    pcl::PCDReader reader;
    if (reader.read(path, blob) < 0) throw InputError(path + ": not a readable PCD file");
    for (const auto& field : blob.fields) {
      has_rgb = has_rgb || field.name == "rgb" || field.name == "rgba";
      for (int a = 0; a < 3; ++a) has_xyz[a] = has_xyz[a] || field.name == std::string(1, static_cast<char>('x' + a));
    }
    if (!has_xyz[0] || !has_xyz[1] || !has_xyz[2]) throw InputError(path + ": the point cloud has no x, y and z fields");
    pcl::fromPCLPointCloud2(blob, points);
  } catch (const pcl::PCLException& e) {
    throw InputError(path + ": not a readable PCD file (" + e.detailedMessage() + ")");
  }
  core::PointCloud cloud;
  cloud.frame = "rig";
  cloud.has_color = has_rgb;
  const Eigen::Matrix3f turn = image_rotation.cast<float>();
  for (const auto& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    core::CloudPoint point;
    point.p = turn * Eigen::Vector3f(p.x, p.y, p.z);
    point.r = p.r, point.g = p.g, point.b = p.b;
    cloud.points.push_back(point);
  }
  if (cloud.points.empty()) throw InputError(path + ": the point cloud has no finite point");
  return cloud;
}

}  // namespace

core::PointCloud cloudFromDepthFile(const std::string& path, const cv::Mat& top, double baseline_m,
                                    const Eigen::Matrix3d& image_rotation) {
  const std::string ext = extensionOf(path);
  if (ext == "tif" || ext == "tiff") return cloudFromRange(path, top, baseline_m, image_rotation);
  if (ext == "pcd") return cloudFromPcd(path, image_rotation);
  throw InputError(path + ": --depth takes a range image (.tif, .tiff) or a point cloud (.pcd)");
}

}  // namespace room_reverb::tool
