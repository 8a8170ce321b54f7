#pragma once
// The colour of a ray in a synthetic capture: which surface it meets (capture_raycast.h),
// that surface's procedural texture (procedural_texture.h), and a view-independent Lambert
// shading, so a surface point has the same colour in both cameras.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/vision/room_raycast.h"
#include "procedural_texture.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/synthetic_capture/capture_generator.h"

namespace room_reverb::core::capture_detail {

struct CapturePainter {
  CaptureGeometry geometry;
  std::vector<MaterialLook> looks;  // by material index
  std::uint64_t seed = 1;
  bool shading = true;
  // A room with a ceiling is lit by a point light a little below the ceiling's centre;
  // an open room by the sun from a fixed direction.
  bool sunlight = false;
  Eigen::Vector3d light_m = Eigen::Vector3d::Zero();  // position, or direction towards the sun
  double falloff_distance_m = 1.0;  // where the point light's intensity has halved
  double ambient = 0.45;            // share of the light that reaches every surface
  // Light sources (CameraImperfections::emitter_labels): by object index, whether it glows,
  // and with what colour (a warm white, RGB grey levels).
  std::vector<bool> emits;
  Rgb emitted = Rgb::Zero();
};

// The room's material names in id order: box faces (kRoomSurfaceNames order, the ceiling
// only when there is one) then objects, each name once, as written in the model.
std::vector<std::string> captureMaterialNames(const RoomModel& room);

CapturePainter makeCapturePainter(const RoomModel& room, const MaterialLibrary& library,
                                  const CaptureOptions& options, const std::vector<std::string>& material_names);

// Unshaded-sky or shaded-surface colour (RGB grey levels) of a ray that produced `hit`.
// `sample_angle_rad` is the angle between neighbouring samples of the image: with the
// distance it gives the footprint on the surface that the texture is filtered to.
Rgb paintHit(const CapturePainter& painter, const Eigen::Vector3d& direction, const SurfaceHit& hit,
             double sample_angle_rad);

}  // namespace room_reverb::core::capture_detail
