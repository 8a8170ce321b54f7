#pragma once
// Synthetic stereo 360° captures with known truth. No licensed capture from a vertically
// aligned pair of 360° cameras exists for the project's rooms, so the visual route is
// developed and tested on rooms rendered here: a RoomModel (synthetic_capture/capture_scene.h reads
// one from a file) seen from two cameras on a vertical baseline, by exact ray casting
// against the room box and its cuboid objects, with procedural textures per material
// (vision/texture_family.h) and, per camera, the range, material and object of every pixel.
//
// The rig: the top camera at rig + R (0, 0, +b/2), the bottom one at rig + R (0, 0, -b/2),
// both with the rig's orientation R (RoomModel::rig_position_m, rig_rotation). Images are
// equirectangular in the convention of vision/equirect.h, in each camera's frame.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/synthetic_capture/photo_textures.h"
#include "room_reverb/vision/dual_fisheye.h"

namespace room_reverb::core {

// Object ids: the box faces in kRoomSurfaceNames order (0 floor, 1 ceiling, 2..5 walls),
// then object k of RoomModel::objects as kCaptureFirstObjectId + k; sky (the open top of
// a room without ceiling) is kCaptureSkyId, in the material id image too.
constexpr std::uint16_t kCaptureFirstObjectId = 6;
constexpr std::uint16_t kCaptureSkyId = 65535;

// What a real camera does to the light between the scene and the file, so that captures
// can be made as hard as real ones. The defaults are an ideal camera (every effect off).
struct CameraImperfections {
  // Colour through the lenses: each camera's colour is rendered as its dual-fisheye image
  // (CaptureOptions::fisheye_calibration) and stitched onto the equirectangular grid by the
  // route's own stitcher (fisheyeToEquirect), as a Theta makes its file: resampled, blended
  // at the two seams, with the lens effects below. The truth images stay those of the
  // camera centre.
  bool through_lenses = false;
  // Each lens's optical centre lies this far ahead of the camera centre along its axis
  // [m]: the two lenses see the scene from points 2 x offset apart, so near things are
  // doubled or cut at the seams. An assumption of about half a body's thickness (1 cm),
  // not a measured Theta figure.
  double lens_offset_m = 0.0;
  // Light lost towards a lens's rim: gain 1 - vignetting (angle / 90°)^2 at `angle` from
  // its axis, so `vignetting` is the share lost at the seam.
  double vignetting = 0.0;
  double back_lens_gain = 1.0;  // the back lens's brightness relative to the front's: a step at the seams
  // Exposure: each camera exposes on its own (two Thetas on auto). The scene's light is
  // multiplied by the gain (and the bottom camera's colour by its white balance) before
  // the sensor clips it at 255.
  double top_exposure = 1.0;
  double bottom_exposure = 1.0;
  Eigen::Vector3d bottom_white_balance = Eigen::Vector3d::Ones();  // R, G, B gains relative to the top camera
  // JPEG compression of each camera's images at this quality (OpenCV's encoder, 1..100),
  // after noise and quantisation; 0: none.
  int jpeg_quality = 0;
  // The camera records its colour at native_scale times the capture's width (lenses,
  // noise, JPEG all at that resolution) and the image is shrunk to the capture's width
  // (pixel-area averaging), as a user shrinks a 5376-pixel Theta still to the route's
  // 2048 (a scale of 2.6; a 4K live stream shrunk to 2048 is 1.9). 1..4.
  int native_scale = 1;
  // Light sources: objects whose label is listed here glow with `emitter_grey` grey levels
  // (before exposure; above 255 they clip to a flat white, as light panels and windows
  // with daylight do in a room exposed for its walls).
  std::vector<std::string> emitter_labels;
  double emitter_grey = 400.0;
  // The cameras as they stand on the bar, each turned by an angle-axis vector [deg]: the
  // top camera against the rig's frame (the bar along its z) and the bottom camera against
  // the top one. Two cameras screwed to a bar stand within a degree or two of each other.
  // The truth images are each camera's as it stands.
  Eigen::Vector3d top_turn_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d bottom_turn_deg = Eigen::Vector3d::Zero();
};

struct CaptureOptions {
  int width = 2048;          // equirect width W [px], even, >= 64; height W / 2
  int supersampling = 2;     // n: n x n colour samples per pixel, averaged (antialiasing), 1..8
  std::uint64_t seed = 1;    // textures and sensor noise; the same seed gives the same bytes
  bool shading = true;       // Lambert from a light near the ceiling plus ambient; off: flat texture colour
  double noise_sigma = 0.0;  // Gaussian sensor noise, standard deviation in grey levels (0: none)
  double baseline_m = 0.2;   // vertical distance between the two camera centres [m]
  // Materials drawn "poorly textured": their texture contrast is scaled by
  // low_texture_contrast, leaving a nearly flat colour (a hard case for stereo matching).
  std::vector<std::string> low_texture_materials;
  double low_texture_contrast = 0.03;
  // Also render each camera as a dual-fisheye image (2S x S, S = width / 2) through the
  // calibration (scaled to S), as a Ricoh Theta records it.
  bool fisheye = false;
  DualFisheyeCalibration fisheye_calibration = idealDualFisheye(1024);
  // Photographic textures (photo_textures.h): a material whose family the set holds is
  // painted, with probability photo_share, with one of that family's photographs (chosen
  // from the seed and the material's name, at its listed width times 0.75..1.33); the
  // others keep their drawn texture. None: every material is drawn.
  std::shared_ptr<const PhotoTextureSet> photo_textures;
  double photo_share = 1.0;
  CameraImperfections camera;
  // Worker threads over image rows (0: the hardware's count). Rows are independent, so
  // the result does not depend on it.
  int threads = 0;
};

struct CameraCapture {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();            // camera centre, room frame
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();    // camera frame -> room frame
  cv::Mat color;        // CV_8UC3, BGR
  cv::Mat range_m;      // CV_32FC1: distance from the camera centre to the surface seen at the
                        // pixel centre [m]; +inf for sky
  cv::Mat material_id;  // CV_16UC1: index into StereoCapture::material_names; kCaptureSkyId for sky
  cv::Mat object_id;    // CV_16UC1: see kCaptureFirstObjectId
  cv::Mat fisheye;      // CV_8UC3 dual-fisheye image when CaptureOptions::fisheye, else empty
};

struct StereoCapture {
  CameraCapture top;
  CameraCapture bottom;
  std::vector<std::string> material_names;  // material id -> name as written in the room model
  std::vector<std::string> object_names;    // object id -> floor, ceiling, walls, object labels
};

// Camera centres of the rig (room frame).
Eigen::Vector3d topCameraPosition(const RoomModel& room, double baseline_m);
Eigen::Vector3d bottomCameraPosition(const RoomModel& room, double baseline_m);

// InputError with a message naming the fault unless the options are usable (width even
// and >= 64, supersampling 1..8, baseline positive and finite, noise sigma finite and >= 0,
// low_texture_contrast in [0, 1], the camera's imperfections in range), every material of the room (and every low-texture
// material) is known to the library or defined inline, and both cameras are strictly
// inside the room box and outside every object.
void validateCapture(const RoomModel& room, const MaterialLibrary& library, const CaptureOptions& options);

// Renders both cameras (validateCapture first).
StereoCapture renderCapture(const RoomModel& room, const MaterialLibrary& library, const CaptureOptions& options);

// Renders one camera at any pose inside the room (the options' baseline is not used; it
// exposes as the rig's top camera). `material_names` receives the material id list.
CameraCapture renderCaptureCamera(const RoomModel& room, const MaterialLibrary& library, const CaptureOptions& options,
                                  const Eigen::Vector3d& position_m, const Eigen::Quaterniond& rotation,
                                  std::vector<std::string>* material_names = nullptr);

}  // namespace room_reverb::core
