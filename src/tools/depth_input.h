#pragma once
// Depth from elsewhere for `room_reverb room-model --depth`: another stereo matcher's,
// a depth camera's or a LiDAR's, instead of the tool's own spherical stereo.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>

#include "room_reverb/vision/point_cloud.h"

namespace room_reverb::tool {

// The point cloud in the aligned rig frame (the rig turned by `image_rotation`, as the
// levelled images are) from:
//  - a range image (.tif/.tiff): 32-bit float, metres from the top camera along each
//    pixel's direction, NaN or 0 where invalid, on the top image's equirectangular grid
//    (what --range writes); coloured from `top`;
//  - a point cloud (.pcd, ASCII or binary, read by PCL): x y z in metres in the rig frame
//    (origin midway between the cameras), with rgb if it has it.
// InputError for another extension, an unreadable file, a range image of the wrong type
// or size, or a cloud with no finite point.
core::PointCloud cloudFromDepthFile(const std::string& path, const cv::Mat& top, double baseline_m,
                                    const Eigen::Matrix3d& image_rotation);

}  // namespace room_reverb::tool
