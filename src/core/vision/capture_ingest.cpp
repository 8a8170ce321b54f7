#include "room_reverb/vision/capture_ingest.h"

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "room_reverb/common/error.h"
#include "room_reverb/vision/equirect_rotation.h"

namespace room_reverb::core {

CaptureImageFormat parseCaptureImageFormat(const std::string& text, const std::string& what) {
  if (text == "equirect") return CaptureImageFormat::kEquirect;
  if (text == "dual_fisheye") return CaptureImageFormat::kDualFisheye;
  throw InputError(what + ": unknown image format '" + text + "' (equirect or dual_fisheye)");
}

LevelingSource parseLevelingSource(const std::string& text, const std::string& what) {
  if (text == "none") return LevelingSource::kNone;
  if (text == "image") return LevelingSource::kImage;
  if (text == "imu") return LevelingSource::kImu;
  if (text == "imu_and_image") return LevelingSource::kImuAndImage;
  throw InputError(what + ": unknown leveling '" + text + "' (none, image, imu or imu_and_image)");
}

namespace {

void checkPair(const cv::Mat& top, const cv::Mat& bottom) {
  if (top.empty() || bottom.empty()) throw InputError("capture: an image is empty");
  if (top.size() != bottom.size()) {
    throw InputError("capture: the top and bottom images differ in size (" + std::to_string(top.cols) + "x" +
                     std::to_string(top.rows) + " and " + std::to_string(bottom.cols) + "x" +
                     std::to_string(bottom.rows) + ")");
  }
  if (top.type() != bottom.type()) throw InputError("capture: the top and bottom images differ in type");
  if (top.cols != 2 * top.rows) {
    throw InputError("capture: the images must be twice as wide as high (equirect or dual fisheye); these are " +
                     std::to_string(top.cols) + "x" + std::to_string(top.rows));
  }
}

}  // namespace

IngestedCapture ingestCapture(const cv::Mat& top, const cv::Mat& bottom, const CaptureIngestOptions& options,
                              const std::optional<Eigen::Quaterniond>& imu_camera_to_world) {
  checkPair(top, bottom);
  if (options.width < 0 || options.width % 2 != 0) throw InputError("capture: the output width must be even and >= 0");
  const bool uses_imu = options.leveling == LevelingSource::kImu || options.leveling == LevelingSource::kImuAndImage;
  if (uses_imu && !imu_camera_to_world) throw InputError("capture: IMU leveling needs the IMU's orientation");

  IngestedCapture out;
  const int width = options.width > 0 ? options.width : top.cols;
  if (options.format == CaptureImageFormat::kDualFisheye) {
    out.top = fisheyeToEquirect(top, options.calibration, width);
    out.bottom = fisheyeToEquirect(bottom, options.calibration, width);
  } else if (width != top.cols) {
    cv::resize(top, out.top, cv::Size(width, width / 2), 0, 0, cv::INTER_AREA);
    cv::resize(bottom, out.bottom, cv::Size(width, width / 2), 0, 0, cv::INTER_AREA);
  } else {
    out.top = top;
    out.bottom = bottom;
  }

  // The pair rectified; the levelling sees the rectified pair (the bottom image's line
  // segments turned by the rectification), and each image is resampled once, through
  // both turns.
  const cv::Mat top_as_captured = out.top, bottom_as_captured = out.bottom;  // headers: no copies
  out.rectification = estimatePairRectification(out.top, out.bottom, options.rectification);
  const PairRectification& pair = out.rectification;
  // A turned bottom image is resampled where the top one is not, or along other
  // fractions of a pixel; bilinear weights smooth each by its own amount and the stereo
  // would match two images of different sharpness. Bicubic keeps both nearly as sharp.
  const int interpolation = pair.applied ? cv::INTER_CUBIC : cv::INTER_LINEAR;
  if (pair.applied) {
    char line[320];
    std::snprintf(line, sizeof line,
                  "pair: the bottom camera stands turned %.2f deg against the top one (%d of %d feature matches "
                  "agree); the pair is rectified",
                  pair.turn_rad * 180.0 / M_PI, pair.inliers, pair.matches);
    out.warnings.emplace_back(line);
  } else if (options.rectification.enabled && !pair.estimated) {
    out.warnings.push_back("pair: too few features match between the two images (" + std::to_string(pair.matches) +
                           ") to tell how the cameras stand; the pair is used as it comes");
  }
  // Both images turned by the levelling's image rotation, the bottom one after its own
  // turn; a turn that is exactly none leaves the image as it is (an interpolating kernel
  // at whole pixels would give it back unchanged).
  const auto turned = [&](const cv::Mat& image, const Eigen::Matrix3d& R) {
    return R.isIdentity(0.0) ? image : rotateEquirect(image, R, interpolation);
  };
  const auto finish = [&]() {
    out.top = turned(top_as_captured, out.leveling.image_rotation);
    out.bottom = turned(bottom_as_captured, out.leveling.image_rotation * pair.bottom_rotation);
    return out;
  };

  switch (options.leveling) {
    case LevelingSource::kNone:
      return finish();
    case LevelingSource::kImu:
      out.leveling = levelingFromImu(*imu_camera_to_world);
      out.leveling.image_rotation.setIdentity();  // no yaw: the images stay as they are
      return finish();
    case LevelingSource::kImage:
    case LevelingSource::kImuAndImage: {
      ManhattanImageOptions manhattan = options.manhattan;
      if (uses_imu) manhattan.known_up = cameraUpFromImu(*imu_camera_to_world);
      try {
        out.manhattan = estimateManhattanFrame(std::vector<cv::Mat>{top_as_captured, bottom_as_captured},
                                               {Eigen::Matrix3d::Identity(), pair.bottom_rotation}, manhattan);
      } catch (const ManhattanStructureError& e) {
        out.level_from_cloud = true;
        out.warnings.push_back(std::string("leveling: ") + e.what() + "; the images are not levelled" +
                               (uses_imu ? " (tilted by the IMU)" : "") + " and the point cloud levels the room");
        if (uses_imu) out.leveling = levelingFromImu(*imu_camera_to_world);
        out.leveling.image_rotation.setIdentity();
        return finish();
      }
      out.leveling = splitLeveling(out.manhattan->camera_to_manhattan);
      break;
    }
  }
  return finish();
}

}  // namespace room_reverb::core
