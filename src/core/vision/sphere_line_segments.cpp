#include "sphere_line_segments.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "equirect_padding.h"
#include "room_reverb/common/parallel_rows.h"

namespace room_reverb::core::vision_detail {
namespace {

// Rotation from a view's optical frame (x right, y down, z along the view) to the camera
// frame, for a view looking along `forward` with its image right along `right`.
Eigen::Matrix3d viewToCamera(const Eigen::Vector3d& forward, const Eigen::Vector3d& right) {
  Eigen::Matrix3d R;
  R.col(0) = right;
  R.col(1) = forward.cross(right);  // down
  R.col(2) = forward;
  return R;
}

std::array<Eigen::Matrix3d, 6> cubeViews() {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  return {viewToCamera(x, -y), viewToCamera(y, x), viewToCamera(-x, y), viewToCamera(-y, -x),
          viewToCamera(z, -y), viewToCamera(-z, -y)};
}

}  // namespace

std::vector<std::vector<SphereSegment>> detectSphereSegments(const std::vector<cv::Mat>& grey_equirects,
                                                             int view_size_px, double view_fov_rad,
                                                             double min_length_rad) {
  if (grey_equirects.empty()) return {};
  const EquirectGeometry g{grey_equirects.front().cols, grey_equirects.front().rows};
  std::vector<cv::Mat> padded;
  for (const cv::Mat& grey : grey_equirects) padded.push_back(padEquirectOnSphere(grey));
  const std::array<Eigen::Matrix3d, 6> views = cubeViews();
  const double focal_px = 0.5 * view_size_px / std::tan(0.5 * view_fov_rad);
  const double centre_px = 0.5 * (view_size_px - 1);  // OpenCV's convention: pixel i's centre at i
  auto ray = [&](const Eigen::Matrix3d& view_to_camera, double x, double y) {
    return (view_to_camera * Eigen::Vector3d((x - centre_px) / focal_px, (y - centre_px) / focal_px, 1.0)).normalized();
  };

  // found[view][image]
  std::array<std::vector<std::vector<SphereSegment>>, 6> found;
  forEachRow(6, 0, [&](int view) {
    const Eigen::Matrix3d& R = views[static_cast<std::size_t>(view)];
    cv::Mat map_x(view_size_px, view_size_px, CV_32FC1), map_y(view_size_px, view_size_px, CV_32FC1);
    for (int row = 0; row < view_size_px; ++row) {
      for (int col = 0; col < view_size_px; ++col) {
        const Eigen::Vector2f p = paddedRemapCoordinates(g, ray(R, col, row));
        map_x.at<float>(row, col) = p.x();
        map_y.at<float>(row, col) = p.y();
      }
    }
    std::vector<std::vector<SphereSegment>>& per_image = found[static_cast<std::size_t>(view)];
    per_image.resize(padded.size());
    const cv::Ptr<cv::LineSegmentDetector> detector = cv::createLineSegmentDetector(cv::LSD_REFINE_STD);
    for (std::size_t image = 0; image < padded.size(); ++image) {
      cv::Mat perspective;
      cv::remap(padded[image], perspective, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
      std::vector<cv::Vec4f> lines;
      detector->detect(perspective, lines);
      for (const cv::Vec4f& l : lines) {
        const Eigen::Vector3d a = ray(R, l[0], l[1]), b = ray(R, l[2], l[3]);
        const Eigen::Vector3d n = a.cross(b);
        const double length = std::atan2(n.norm(), a.dot(b));
        if (length >= min_length_rad) per_image[image].push_back({n.normalized(), length});
      }
    }
  });
  std::vector<std::vector<SphereSegment>> segments(padded.size());
  for (std::size_t image = 0; image < padded.size(); ++image) {
    for (const auto& view_segments : found) {
      segments[image].insert(segments[image].end(), view_segments[image].begin(), view_segments[image].end());
    }
  }
  return segments;
}

}  // namespace room_reverb::core::vision_detail
