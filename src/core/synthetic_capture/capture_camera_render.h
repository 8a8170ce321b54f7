#pragma once
// Rendering one camera of a synthetic capture: the equirectangular colour and truth
// images, and the dual-fisheye colour image, before sensor noise and quantisation.
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "capture_painter.h"
#include "room_reverb/vision/dual_fisheye.h"

namespace room_reverb::core::capture_detail {

struct EquirectRender {
  cv::Mat color;        // CV_32FC3, BGR grey levels (unrounded)
  cv::Mat range_m;      // CV_32FC1
  cv::Mat material_id;  // CV_16UC1
  cv::Mat object_id;    // CV_16UC1
};

// `camera_to_room` turns camera-frame directions into the room frame. Colour is the mean of
// supersampling x supersampling samples per pixel; range and ids are those of the ray
// through the pixel centre (exact truth, not a blend of neighbours).
EquirectRender renderEquirect(const CapturePainter& painter, const Eigen::Vector3d& position_m,
                              const Eigen::Matrix3d& camera_to_room, int width, int supersampling, int threads);

// A dual-fisheye image (CV_32FC3, BGR, 2S x S for calibration.size_px = S): every pixel
// averages its samples that fall inside an image circle, black outside.
cv::Mat renderDualFisheye(const CapturePainter& painter, const Eigen::Vector3d& position_m,
                          const Eigen::Matrix3d& camera_to_room, const DualFisheyeCalibration& calibration,
                          int supersampling, int threads);

}  // namespace room_reverb::core::capture_detail
