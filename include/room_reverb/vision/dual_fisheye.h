#pragma once
// Dual-fisheye 360° cameras (Ricoh Theta style): two back-to-back lenses of more than
// 180° each, recorded side by side in one image of 2S x S pixels (the front lens in the
// left S x S half, the back lens in the right half). The calibration, the equidistant
// projection of each lens both ways, and stitching into the project's equirectangular
// image (vision/equirect.h).
//
// Frames: the camera frame is REP 103 (x forward, y left, z up). A lens's optical frame
// has z along its axis, x to the image's right and y down the image (the OpenCV camera
// convention). The front lens looks along +x with image right = -y; the back lens looks
// along -x with image right = +y; both have image up = +z. A lens's rotation (from its
// calibration) turns this nominal mount in the camera frame.
//
// Pixel coordinates in a lens half use the convention of equirect.h: continuous (x, y)
// with pixel (i, j) covering [i, i+1) x [j, j+1), so the centre of pixel (i, j) is at
// (i + 0.5, j + 0.5), and x counts from the half's own left edge.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace room_reverb::core {

struct FisheyeLens {
  Eigen::Vector2d center_px = Eigen::Vector2d::Zero();  // principal point (cx, cy) in the lens's half [px]
  double radius_px = 0.0;    // image circle: distance from the centre of the ray at fov/2 [px]
  double fov_deg = 190.0;    // full field of view of the image circle [deg]
  // Deviation of the lens from its nominal mount as roll, pitch, yaw [deg] about the
  // camera's x, y, z (applied as Rz(yaw) Ry(pitch) Rx(roll) after the nominal mount).
  Eigen::Vector3d rotation_rpy_deg = Eigen::Vector3d::Zero();
};

enum class FisheyeSide { kFront, kBack };

struct DualFisheyeCalibration {
  int size_px = 1024;  // S: each lens's half is S x S; the dual image is 2S x S
  FisheyeLens front;   // left half, looks along +x
  FisheyeLens back;    // right half, looks along -x

  const FisheyeLens& lens(FisheyeSide side) const { return side == FisheyeSide::kFront ? front : back; }
};

// Both lenses centred in their halves, image circle radius 0.48 S for a 190° field of view,
// no rotation.
DualFisheyeCalibration idealDualFisheye(int size_px);
// The same lenses for halves of `size_px` instead of calibration.size_px (pixel lengths
// scaled; angles unchanged).
DualFisheyeCalibration scaledDualFisheye(const DualFisheyeCalibration& calibration, int size_px);
// InputError naming `source` and the key unless the sizes are positive, the field of view
// is in (180°, 360°) for both lenses (they must overlap to be stitched), the rotations are
// finite and small (under 10°) and each circle's centre lies inside its half.
void validateDualFisheyeCalibration(const DualFisheyeCalibration& calibration, const std::string& source);

// YAML (config/dual_fisheye.yaml documents every key). Load/parse throw InputError with
// the key at fault.
DualFisheyeCalibration loadDualFisheyeCalibration(const std::string& path);
DualFisheyeCalibration parseDualFisheyeCalibration(const std::string& yaml_text, const std::string& source);
std::string dualFisheyeCalibrationToYaml(const DualFisheyeCalibration& calibration);
void saveDualFisheyeCalibration(const std::string& path, const DualFisheyeCalibration& calibration);
// $ROOM_REVERB_DUAL_FISHEYE if set, else config/dual_fisheye.yaml of the source tree.
std::string defaultDualFisheyeCalibrationPath();

// Rotation from a lens's optical frame to the camera frame (nominal mount, then the lens's
// own rotation).
Eigen::Matrix3d fisheyeLensToCamera(const FisheyeLens& lens, FisheyeSide side);
// Angle [rad] between a camera-frame direction and the lens's axis.
double fisheyeAngleFromAxis(const FisheyeLens& lens, FisheyeSide side, const Eigen::Vector3d& direction);
// Equidistant projection r = radius_px * angle / (fov / 2): the pixel coordinates (in the
// lens's half) of a camera-frame direction, or nothing beyond half the field of view.
std::optional<Eigen::Vector2d> fisheyeProject(const FisheyeLens& lens, FisheyeSide side, const Eigen::Vector3d& direction);
// The unit camera-frame direction of pixel coordinates in the lens's half, or nothing
// outside the image circle.
std::optional<Eigen::Vector3d> fisheyeUnproject(const FisheyeLens& lens, FisheyeSide side, const Eigen::Vector2d& pixel);

// Stitches a dual-fisheye image (2S x S, any depth and channel count OpenCV can remap) into
// an equirectangular image `width` x `width` / 2 of the same type. A direction seen by one
// lens only is sampled from it (bilinear); in the overlap, where both lenses see it (about
// 10° for two 190° lenses), the two are blended with weights that fall smoothly to zero at
// each circle's edge, so the seam has no step. The calibration is scaled to the image when
// its size_px differs. InputError for an image that is not 2:1, a width that is odd or
// under 64, or an invalid calibration.
cv::Mat fisheyeToEquirect(const cv::Mat& dual_image, const DualFisheyeCalibration& calibration, int width);

}  // namespace room_reverb::core
