#pragma once
// Rectified surface patches for material classification: squares of a fixed size laid on
// every plane of a room model (the box's faces, the sides and tops of its cuboids) and
// filled from an equirectangular image by projecting each patch pixel's surface point
// into the camera.
//
// Why not tiles of the equirect image: its rows are stretched towards the poles and a
// texture's scale in pixels changes with its distance. A patch laid on the surface is
// seen face-on at a known metric scale (a brick is the same number of pixels at 1 m and
// at 5 m; only the sharpness differs), its rows run along the surface's vertical, and it
// covers a known area of the surface, which makes the vote over a face area-weighted.
// Both the training (on generated rooms, with their true models) and the classification
// of a fitted layout cut their patches here, so they see the same kind of image.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/vision/material_classifier.h"

namespace room_reverb::core::material_detail {

// A rectangle of the model, in the room frame: p = center + s u + t v for |s| <= half_width,
// |t| <= half_height; v is vertical on vertical faces; the normal points to where it is
// seen from (into the room for the box, out of an object).
struct SurfaceRect {
  int target = 0;  // the capture's object ids: 0..5 box faces (kRoomSurfaceNames), 6 + k object k
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX(), v = Eigen::Vector3d::UnitY(), normal = Eigen::Vector3d::UnitZ();
  double half_width_m = 0.0, half_height_m = 0.0;
};

// The box's faces (no ceiling when has_ceiling is false), then each object's four sides
// and top (a bottom on the floor is never seen).
std::vector<SurfaceRect> modelSurfaceRects(const RoomModel& model);

struct SurfacePatch {
  int target = 0;
  double s_m = 0.0, t_m = 0.0;  // the patch's centre on its rectangle (SurfaceRect's s and t)
  cv::Mat bgr;                // pixels x pixels CV_8UC3; black outside the mask
  cv::Mat mask;               // CV_8UC1, 255 where the surface is seen
  double area_m2 = 0.0;       // area of the surface under the mask
  double source_pixels = 0.0; // image pixels across the patch at its range and slant
};

struct PatchSampling {
  MaterialPatchGeometry geometry;
  // A patch is kept if this fraction of its part on the surface is seen (at least 64
  // pixels), and the image resolves it with at least min_source_pixels pixels across
  // (fewer show only its mean colour).
  double min_coverage = 0.25;
  double min_source_pixels = 6.0;
  // Points seen at more grazing angles than this cosine are left out of the mask.
  double min_cos_incidence = 0.1;
  // A rectangle with more patch positions than this keeps those whose centres are nearest
  // the camera (0: no limit, as the training takes them). Classifying a fitted room
  // limits it (SurfaceMaterialOptions::max_patches_per_face): a face's vote settles
  // before (at 100, every face of 40 development rooms and of the courtyard scene gets
  // the material it gets from all its patches), and without a limit the step's time grows
  // with the faces' area (the courtyard's ground and walls hold 250-550 each). The
  // nearest are the best resolved, and they lie side by side, as the floor's and
  // ceiling's joints need.
  int max_patches_per_rect = 0;
  int threads = 0;  // 0: all cores
};

// Patches of the surfaces of `model` seen in `color` (CV_8UC3 equirect, width = 2 x
// height) by a camera at `room_from_camera` (camera frame -> room frame; the camera
// inside the box). Ordered by surface, then along it; the same for any thread count.
std::vector<SurfacePatch> sampleSurfacePatches(const cv::Mat& color, const RoomModel& model,
                                               const Eigen::Isometry3d& room_from_camera, const PatchSampling& sampling);

// The material features (vision/material_features.h) of each patch, one row each.
cv::Mat patchFeatures(const std::vector<const SurfacePatch*>& patches, int threads);

}  // namespace room_reverb::core::material_detail
