#include "room_reverb/synthetic_capture/capture_generator.h"

#include <cmath>
#include <cstring>
#include <sstream>

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
  if (options.fisheye) validateDualFisheyeCalibration(options.fisheye_calibration, "capture fisheye calibration");
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

CameraCapture renderCamera(const CapturePainter& painter, const CaptureOptions& options, const Eigen::Vector3d& position,
                           const Eigen::Quaterniond& rotation, std::uint64_t noise_stream) {
  CameraCapture camera;
  camera.position_m = position;
  camera.rotation = rotation;
  const Eigen::Matrix3d camera_to_room = rotation.toRotationMatrix();
  EquirectRender render = renderEquirect(painter, position, camera_to_room, options.width, options.supersampling, options.threads);
  camera.color = quantizeWithNoise(render.color, options.noise_sigma, options.seed, 2 * noise_stream);
  camera.range_m = render.range_m;
  camera.material_id = render.material_id;
  camera.object_id = render.object_id;
  if (options.fisheye) {
    const DualFisheyeCalibration calibration = scaledDualFisheye(options.fisheye_calibration, options.width / 2);
    const cv::Mat fisheye = renderDualFisheye(painter, position, camera_to_room, calibration, options.supersampling, options.threads);
    camera.fisheye = quantizeWithNoise(fisheye, options.noise_sigma, options.seed, 2 * noise_stream + 1);
  }
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
  const Eigen::Quaterniond rotation = room.rig_rotation.normalized();
  capture.top = renderCamera(painter, options, topCameraPosition(room, options.baseline_m), rotation, 0);
  capture.bottom = renderCamera(painter, options, bottomCameraPosition(room, options.baseline_m), rotation, 1);
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
  return renderCamera(painter, options, position_m, rotation.normalized(), stream);
}

}  // namespace room_reverb::core
