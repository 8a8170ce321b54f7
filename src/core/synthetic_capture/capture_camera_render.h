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
// through the pixel centre (exact truth, not a blend of neighbours). Without `colour` the
// colour image is left empty (the truth alone, for a capture whose colour comes through
// the lenses).
EquirectRender renderEquirect(const CapturePainter& painter, const Eigen::Vector3d& position_m,
                              const Eigen::Matrix3d& camera_to_room, int width, int supersampling, int threads,
                              bool colour = true);

// What the two lenses of a dual-fisheye camera add (CameraImperfections).
struct LensEffects {
  double offset_m = 0.0;    // each lens's optical centre ahead of the camera centre along its axis
  double vignetting = 0.0;  // share of the light lost at 90° from the axis (quadratic in the angle)
  double back_gain = 1.0;   // back lens relative to the front
};

// A dual-fisheye image (CV_32FC3, BGR, 2S x S for calibration.size_px = S): every pixel
// averages its samples that fall inside an image circle, black outside. Each lens sees
// from its own optical centre and with its own gain and vignetting (`lens`).
cv::Mat renderDualFisheye(const CapturePainter& painter, const Eigen::Vector3d& position_m,
                          const Eigen::Matrix3d& camera_to_room, const DualFisheyeCalibration& calibration,
                          int supersampling, int threads, const LensEffects& lens = {});

}  // namespace room_reverb::core::capture_detail
