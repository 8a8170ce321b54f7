#pragma once
// What the capture_ingest node does to a rig's two images before the stereo: dual-fisheye
// images stitched to equirectangular (vision/dual_fisheye.h), then both turned about the
// baseline to face the room's walls and the rig's tilt measured (vision/image_leveling.h
// says why the tilt is reported, not applied), from the images' straight edges
// (vision/manhattan_from_image.h), an IMU, or both.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/vision/dual_fisheye.h"
#include "room_reverb/vision/image_leveling.h"
#include "room_reverb/vision/manhattan_from_image.h"
#include "room_reverb/vision/pair_rectification.h"

namespace room_reverb::core {

enum class CaptureImageFormat { kEquirect, kDualFisheye };

enum class LevelingSource {
  kNone,         // images passed on as they are
  kImage,        // tilt and yaw from the images' Manhattan frame
  kImu,          // tilt from the IMU; no yaw (an IMU's heading is not the room's)
  kImuAndImage,  // tilt from the IMU, yaw about its up from the images
};

// "equirect" / "dual_fisheye"; "none", "image", "imu", "imu_and_image". InputError naming
// `what` and the accepted values otherwise.
CaptureImageFormat parseCaptureImageFormat(const std::string& text, const std::string& what);
LevelingSource parseLevelingSource(const std::string& text, const std::string& what);

struct CaptureIngestOptions {
  CaptureImageFormat format = CaptureImageFormat::kEquirect;
  DualFisheyeCalibration calibration = idealDualFisheye(1024);  // for kDualFisheye
  int width = 0;  // output equirect width [px]; 0: the input's width (2 S for dual fisheye)
  LevelingSource leveling = LevelingSource::kImage;
  ManhattanImageOptions manhattan;
  // How the two cameras stand on the bar, found from the pair and taken out before the
  // levelling (vision/pair_rectification.h); `enabled` false: the pair as it comes.
  PairRectificationOptions rectification;
};

struct IngestedCapture {
  // Equirectangular, rectified (the bottom camera facing as the top one) and turned by
  // leveling.image_rotation: the bottom image is the input's turned by
  // leveling.image_rotation * rectification.bottom_rotation.
  cv::Mat top;
  cv::Mat bottom;
  PairRectification rectification;
  ImageLeveling leveling;  // identity for LevelingSource::kNone
  std::optional<ManhattanImageEstimate> manhattan;  // when the images were used
  // The images asked to level the capture show too little Manhattan structure: they are
  // used as captured (about the baseline; an IMU's tilt where one is used) and the cloud
  // levels the room (VisualRouteOptions::level_from_cloud).
  bool level_from_cloud = false;
  std::vector<std::string> warnings;  // one line each, for the user
};

// InputError for images of different sizes or types, empty images, an image of the wrong
// shape for the format (equirect and dual fisheye are both 2:1), an IMU leveling without
// `imu_camera_to_world`, and as the stitching and the Manhattan estimate report (a black,
// saturated or featureless image). Images with edges but too little Manhattan structure
// are not an error: see IngestedCapture::level_from_cloud.
IngestedCapture ingestCapture(const cv::Mat& top, const cv::Mat& bottom, const CaptureIngestOptions& options,
                              const std::optional<Eigen::Quaterniond>& imu_camera_to_world = std::nullopt);

}  // namespace room_reverb::core
