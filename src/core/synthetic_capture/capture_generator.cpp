#include "room_reverb/synthetic_capture/capture_generator.h"

#include <cmath>
#include <cstring>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "capture_camera_render.h"
#include "capture_painter.h"
#include "room_reverb/common/error.h"
#include "sensor_noise.h"
#include "value_noise.h"

namespace room_reverb::core {
namespace {

using namespace capture_detail;

// Plain decimals for messages ("0.1", not std::to_string's "0.100000").
std::string text(double value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

std::string vectorText(const Eigen::Vector3d& v) { return "[" + text(v.x()) + ", " + text(v.y()) + ", " + text(v.z()) + "]"; }

void checkCamera(const CameraImperfections& c) {
  const auto gain = [](double value, const std::string& key) {
    if (!(value > 0.0) || !std::isfinite(value)) throw InputError("capture camera." + key + " " + text(value) + ": must be a positive, finite gain");
  };
  if (!(c.lens_offset_m >= 0.0 && c.lens_offset_m <= 0.05)) {
    throw InputError("capture camera.lens_offset_m " + text(c.lens_offset_m) + ": must be 0 to 0.05 m (a lens's centre ahead of the camera's)");
  }
  if (!(c.vignetting >= 0.0 && c.vignetting < 1.0)) {
    throw InputError("capture camera.vignetting " + text(c.vignetting) + ": must be in [0, 1) (the share of light lost at 90 degrees)");
  }
  gain(c.back_lens_gain, "back_lens_gain");
  gain(c.top_exposure, "top_exposure");
  gain(c.bottom_exposure, "bottom_exposure");
  for (int i = 0; i < 3; ++i) gain(c.bottom_white_balance[i], "bottom_white_balance");
  if (c.native_scale < 1 || c.native_scale > 4) {
    throw InputError("capture camera.native_scale " + std::to_string(c.native_scale) + ": must be 1 to 4 (native width over the capture's)");
  }
  if (c.jpeg_quality < 0 || c.jpeg_quality > 100) {
    throw InputError("capture camera.jpeg_quality " + std::to_string(c.jpeg_quality) + ": must be 0 (no compression) or 1 to 100");
  }
  if (!(c.emitter_grey >= 0.0) || !std::isfinite(c.emitter_grey)) {
    throw InputError("capture camera.emitter_grey " + text(c.emitter_grey) + ": must be a finite brightness >= 0 in grey levels");
  }
  for (const auto& [key, turn] : {std::pair{"top_turn_deg", c.top_turn_deg}, std::pair{"bottom_turn_deg", c.bottom_turn_deg}}) {
    if (!turn.allFinite() || turn.norm() > 10.0) {
      throw InputError(std::string("capture camera.") + key + " " + vectorText(turn) + ": must be a turn of at most 10 degrees");
    }
  }
}

// An angle-axis vector in degrees as a rotation.
Eigen::Quaterniond turnOf(const Eigen::Vector3d& turn_deg) {
  const double angle = turn_deg.norm() * M_PI / 180.0;
  return angle > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, turn_deg.normalized())) : Eigen::Quaterniond::Identity();
}

void checkOptions(const CaptureOptions& options) {
  if (options.width < 64 || options.width % 2 != 0) {
    throw InputError("capture width " + std::to_string(options.width) +
                     ": must be even and at least 64 pixels (the height is width / 2)");
  }
  if (options.supersampling < 1 || options.supersampling > 8) {
    throw InputError("capture supersampling " + std::to_string(options.supersampling) + ": must be 1 to 8 (n x n samples per pixel)");
  }
  if (!(options.baseline_m > 0.0) || !std::isfinite(options.baseline_m)) {
    throw InputError("capture baseline_m " + text(options.baseline_m) +
                     ": must be a positive, finite distance in metres between the two cameras");
  }
  if (!(options.noise_sigma >= 0.0) || !std::isfinite(options.noise_sigma)) {
    throw InputError("capture noise_sigma " + text(options.noise_sigma) + ": must be a finite number of grey levels >= 0");
  }
  if (!(options.low_texture_contrast >= 0.0 && options.low_texture_contrast <= 1.0)) {
    throw InputError("capture low_texture_contrast " + text(options.low_texture_contrast) + ": must be in [0, 1]");
  }
  if (!(options.photo_share >= 0.0 && options.photo_share <= 1.0)) {
    throw InputError("capture photo_share " + text(options.photo_share) + ": must be in [0, 1]");
  }
  if (options.threads < 0) throw InputError("capture threads: must be 0 (all cores) or more");
  if (options.fisheye || options.camera.through_lenses) {
    validateDualFisheyeCalibration(options.fisheye_calibration, "capture fisheye calibration");
  }
  checkCamera(options.camera);
}

// InputError unless a camera centre is strictly inside the box and outside every object.
void checkCameraPlace(const RoomModel& room, const Eigen::Vector3d& position, const std::string& which) {
  const bool inside = (position.array() > 0.0).all() && (position.array() < room.size_m.array()).all();
  if (!position.allFinite() || !inside) {
    throw InputError(which + " at " + vectorText(position) + " is outside the room box [0, " + text(room.size_m.x()) +
                     "] x [0, " + text(room.size_m.y()) + "] x [0, " + text(room.size_m.z()) + "]; move rig_in_room.position_m or shorten the baseline");
  }
  const CaptureGeometry geometry = makeCaptureGeometry(room, captureMaterialNames(room));
  for (std::size_t k = 0; k < geometry.objects.size(); ++k) {
    if (insideCuboid(geometry.objects[k], position)) {
      throw InputError(which + " at " + vectorText(position) + " is inside objects[" + std::to_string(k) + "] (" +
                       room.objects[k].label + "); move rig_in_room.position_m");
    }
  }
}

void checkMaterials(const RoomModel& room, const MaterialLibrary& library, const CaptureOptions& options) {
  const MaterialLibrary materials = materialsFor(room, library);  // names every unknown face or object material
  for (const std::string& name : options.low_texture_materials) {
    try {
      materials.get(name);
    } catch (const InputError& e) {
      throw InputError(std::string("capture.low_texture_materials: ") + e.what());
    }
  }
}

// How one camera exposes its light: its gain and white balance.
struct Exposure {
  double gain = 1.0;
  Eigen::Vector3d white_balance_rgb = Eigen::Vector3d::Ones();
};

// The top camera's exposure (white balance is relative to it), which a lone camera has too.
Exposure topExposure(const CaptureOptions& options) { return {options.camera.top_exposure, Eigen::Vector3d::Ones()}; }

// Exposure, noise, clipping and quantisation, JPEG: the sensor and the encoder.
cv::Mat recorded(const cv::Mat& light, const CaptureOptions& options, const Exposure& exposure, std::uint64_t stream) {
  cv::Mat image = quantizeWithNoise(exposed(light, exposure.gain, exposure.white_balance_rgb), options.noise_sigma, options.seed, stream);
  return options.camera.jpeg_quality > 0 ? jpegRoundTrip(image, options.camera.jpeg_quality) : image;
}

// An image (2:1) shrunk to `width` by pixel-area averaging; unchanged at that width.
cv::Mat shrunk(const cv::Mat& image, int width) {
  if (image.cols == width) return image;
  cv::Mat out;
  cv::resize(image, out, cv::Size(width, width / 2), 0.0, 0.0, cv::INTER_AREA);
  return out;
}

CameraCapture renderCamera(const CapturePainter& painter, const CaptureOptions& options, const Eigen::Vector3d& position,
                           const Eigen::Quaterniond& rotation, const Exposure& exposure, std::uint64_t noise_stream) {
  CameraCapture camera;
  camera.position_m = position;
  camera.rotation = rotation;
  const Eigen::Matrix3d camera_to_room = rotation.toRotationMatrix();
  const CameraImperfections& c = options.camera;
  // The colour at the camera's own resolution, the truth at the capture's.
  const int native_width = c.native_scale * options.width;
  const bool colour_with_truth = !c.through_lenses && c.native_scale == 1;
  EquirectRender render =
      renderEquirect(painter, position, camera_to_room, options.width, options.supersampling, options.threads, colour_with_truth);
  camera.range_m = render.range_m;
  camera.material_id = render.material_id;
  camera.object_id = render.object_id;
  cv::Mat light = render.color;
  cv::Mat fisheye;
  if (options.fisheye || c.through_lenses) {
    const DualFisheyeCalibration calibration = scaledDualFisheye(options.fisheye_calibration, native_width / 2);
    const LensEffects lens{c.lens_offset_m, c.vignetting, c.back_lens_gain};
    fisheye = renderDualFisheye(painter, position, camera_to_room, calibration, options.supersampling, options.threads, lens);
    if (c.through_lenses) light = fisheyeToEquirect(fisheye, calibration, native_width);
  }
  if (light.empty()) {
    light = renderEquirect(painter, position, camera_to_room, native_width, options.supersampling, options.threads).color;
  }
  camera.color = shrunk(recorded(light, options, exposure, 2 * noise_stream), options.width);
  if (options.fisheye) camera.fisheye = shrunk(recorded(fisheye, options, exposure, 2 * noise_stream + 1), options.width);
  return camera;
}

void checkObjectCount(const RoomModel& room) {
  if (room.objects.size() > kCaptureSkyId - kCaptureFirstObjectId) {
    throw InputError("the room has " + std::to_string(room.objects.size()) + " objects; the 16-bit object id image holds at most " +
                     std::to_string(kCaptureSkyId - kCaptureFirstObjectId));
  }
}

}  // namespace

Eigen::Vector3d topCameraPosition(const RoomModel& room, double baseline_m) {
  return room.rig_position_m + room.rig_rotation * Eigen::Vector3d(0.0, 0.0, 0.5 * baseline_m);
}

Eigen::Vector3d bottomCameraPosition(const RoomModel& room, double baseline_m) {
  return room.rig_position_m - room.rig_rotation * Eigen::Vector3d(0.0, 0.0, 0.5 * baseline_m);
}

void validateCapture(const RoomModel& room, const MaterialLibrary& library, const CaptureOptions& options) {
  roomModelToMesh(room);  // the room model's own checks (sizes, names, unit rotation)
  checkObjectCount(room);
  checkOptions(options);
  checkMaterials(room, library, options);
  const double b = options.baseline_m;
  checkCameraPlace(room, topCameraPosition(room, b), "the top camera (rig + " + text(0.5 * b) + " m along the rig's z)");
  checkCameraPlace(room, bottomCameraPosition(room, b), "the bottom camera (rig - " + text(0.5 * b) + " m along the rig's z)");
}

StereoCapture renderCapture(const RoomModel& room, const MaterialLibrary& library, const CaptureOptions& options) {
  validateCapture(room, library, options);
  StereoCapture capture;
  capture.material_names = captureMaterialNames(room);
  for (const char* face : kRoomSurfaceNames) capture.object_names.emplace_back(face);
  for (const CuboidObject& object : room.objects) capture.object_names.push_back(object.label);
  const CapturePainter painter = makeCapturePainter(room, library, options, capture.material_names);
  const Eigen::Quaterniond top_rotation = room.rig_rotation.normalized() * turnOf(options.camera.top_turn_deg);
  const Eigen::Quaterniond bottom_rotation = top_rotation * turnOf(options.camera.bottom_turn_deg);
  const Exposure bottom{options.camera.bottom_exposure, options.camera.bottom_white_balance};
  capture.top = renderCamera(painter, options, topCameraPosition(room, options.baseline_m), top_rotation, topExposure(options), 0);
  capture.bottom = renderCamera(painter, options, bottomCameraPosition(room, options.baseline_m), bottom_rotation, bottom, 1);
  return capture;
}

CameraCapture renderCaptureCamera(const RoomModel& room, const MaterialLibrary& library, const CaptureOptions& options,
                                  const Eigen::Vector3d& position_m, const Eigen::Quaterniond& rotation,
                                  std::vector<std::string>* material_names) {
  roomModelToMesh(room);
  checkObjectCount(room);
  checkOptions(options);
  checkMaterials(room, library, options);
  checkCameraPlace(room, position_m, "the camera");
  const std::vector<std::string> names = captureMaterialNames(room);
  if (material_names != nullptr) *material_names = names;
  const CapturePainter painter = makeCapturePainter(room, library, options, names);
  // An arbitrary camera's noise stream comes from its position, so that two cameras
  // rendered with one seed do not share their noise (streams 0 and 1 are the rig's).
  std::uint64_t stream = 0x2c1b3c6dULL;
  for (int i = 0; i < 3; ++i) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &position_m[i], sizeof bits);
    stream = hashCombine(stream, bits);
  }
  stream = 2 + (stream >> 2);
  return renderCamera(painter, options, position_m, rotation.normalized(), topExposure(options), stream);
}

}  // namespace room_reverb::core
