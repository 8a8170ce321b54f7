#pragma once
// The point cloud of a spherical depth image: each valid pixel of the top camera's range
// image as a point in the rig frame (the top camera is at +b/2 on the rig's z axis, with
// the rig's axes), coloured from the top image and, where a label image is given, with its
// surface hint.
#include <opencv2/core.hpp>
#include <string>

#include "room_reverb/vision/point_cloud.h"
#include "room_reverb/vision/spherical_stereo.h"

namespace room_reverb::core {

struct DepthCloudOptions {
  int stride = 1;              // every stride-th pixel along both axes (a lighter cloud)
  // Points from hole filling too. Off by default: a filled range is an interpolation
  // across a hole the matcher could not range, often at an object's edge, and its points
  // stretch the furniture cuboids of the layout fit (room_layout.h) without adding
  // anything the measured points around the hole do not show.
  bool include_filled = false;
};

// InputError when the depth and the colour image differ in size, the colour image is not
// 8-bit BGR or grey, `hints` (optional, CV_16UC1 SurfaceHint values) differs in size, the
// baseline is not positive, or the stride is below 1.
PointCloud depthToPointCloud(const SphericalDepth& depth, const cv::Mat& top_color, double baseline_m,
                             const DepthCloudOptions& options = {}, const cv::Mat& hints = cv::Mat());

// A range image from elsewhere (another stereo matcher, a depth camera or a LiDAR
// resampled to the top camera's equirect grid) as the depth the cloud is made from:
// `range_m` is CV_32FC1, metres from the top camera along each pixel's direction, NaN, 0
// or negative where invalid, the size of the top image. `what` names it in errors.
// InputError for another type or size, or no valid range.
SphericalDepth depthFromRangeImage(const cv::Mat& range_m, const cv::Size& top_size, const std::string& what);

}  // namespace room_reverb::core
