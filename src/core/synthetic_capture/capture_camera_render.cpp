#include "capture_camera_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "room_reverb/common/parallel_rows.h"
#include "room_reverb/vision/equirect.h"

namespace room_reverb::core::capture_detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

void storeBgr(float* pixel, const Rgb& rgb) {
  pixel[0] = static_cast<float>(rgb[2]);
  pixel[1] = static_cast<float>(rgb[1]);
  pixel[2] = static_cast<float>(rgb[0]);
}

}  // namespace

EquirectRender renderEquirect(const CapturePainter& painter, const Eigen::Vector3d& position_m,
                              const Eigen::Matrix3d& camera_to_room, int width, int supersampling, int threads,
                              bool colour) {
  const EquirectGeometry g{width, width / 2};
  EquirectRender out;
  if (colour) out.color.create(g.height, g.width, CV_32FC3);
  out.range_m.create(g.height, g.width, CV_32FC1);
  out.material_id.create(g.height, g.width, CV_16UC1);
  out.object_id.create(g.height, g.width, CV_16UC1);
  const int n = supersampling;
  // Rows are pi / H apart in elevation; columns closer than that except at the equator.
  // The larger spacing sets the footprint, so no texture detail aliases anywhere.
  const double sample_angle = kPi / g.height / n;

  forEachRow(g.height, threads, [&](int row) {
    float* color = colour ? out.color.ptr<float>(row) : nullptr;
    float* range = out.range_m.ptr<float>(row);
    auto* material = out.material_id.ptr<std::uint16_t>(row);
    auto* object = out.object_id.ptr<std::uint16_t>(row);
    for (int col = 0; col < g.width; ++col) {
      const Eigen::Vector3d centre = camera_to_room * equirectPixelDirection(g, col, row);
      const SurfaceHit truth = castRay(painter.geometry, position_m, centre);
      range[col] = truth.sky ? std::numeric_limits<float>::infinity() : static_cast<float>(truth.distance_m);
      material[col] = truth.sky ? kCaptureSkyId : static_cast<std::uint16_t>(truth.material);
      object[col] = truth.sky ? kCaptureSkyId : truth.object_id;
      if (color == nullptr) continue;

      Rgb sum = Rgb::Zero();
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          // equirectPixelDirection takes the pixel index and adds 0.5 itself, so a
          // sub-pixel position (i + 0.5) / n inside the pixel is index + that - 0.5.
          const double du = (j + 0.5) / n - 0.5, dv = (i + 0.5) / n - 0.5;
          const bool at_centre = du == 0.0 && dv == 0.0;
          const Eigen::Vector3d d = at_centre ? centre : Eigen::Vector3d(camera_to_room * equirectPixelDirection(g, col + du, row + dv));
          sum += paintHit(painter, d, at_centre ? truth : castRay(painter.geometry, position_m, d), sample_angle);
        }
      }
      storeBgr(color + 3 * col, sum / (n * n));
    }
  });
  return out;
}

cv::Mat renderDualFisheye(const CapturePainter& painter, const Eigen::Vector3d& position_m,
                          const Eigen::Matrix3d& camera_to_room, const DualFisheyeCalibration& calibration,
                          int supersampling, int threads, const LensEffects& effects) {
  const int size = calibration.size_px;
  const Eigen::Vector3d axis = camera_to_room.col(0);
  const Eigen::Vector3d front_centre = position_m + effects.offset_m * axis;
  const Eigen::Vector3d back_centre = position_m - effects.offset_m * axis;
  cv::Mat out(size, 2 * size, CV_32FC3);
  const int n = supersampling;
  forEachRow(size, threads, [&](int row) {
    float* color = out.ptr<float>(row);
    for (int col = 0; col < 2 * size; ++col) {
      const FisheyeSide side = col < size ? FisheyeSide::kFront : FisheyeSide::kBack;
      const FisheyeLens& lens = calibration.lens(side);
      const int x0 = col < size ? col : col - size;
      const Eigen::Vector3d& centre = side == FisheyeSide::kFront ? front_centre : back_centre;
      const double lens_gain = side == FisheyeSide::kFront ? 1.0 : effects.back_gain;
      // Equidistant: neighbouring samples are a constant angle apart along the radius.
      const double sample_angle = 0.5 * lens.fov_deg * kPi / 180.0 / lens.radius_px / n;
      Rgb sum = Rgb::Zero();
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const Eigen::Vector2d pixel(x0 + (j + 0.5) / n, row + (i + 0.5) / n);
          const auto direction = fisheyeUnproject(lens, side, pixel);
          if (!direction) continue;  // outside the image circle: black
          const Eigen::Vector3d d = camera_to_room * *direction;
          const double off_axis = fisheyeAngleFromAxis(lens, side, *direction) / (0.5 * kPi);
          const double gain = lens_gain * std::max(0.0, 1.0 - effects.vignetting * off_axis * off_axis);
          sum += gain * paintHit(painter, d, castRay(painter.geometry, centre, d), sample_angle);
        }
      }
      storeBgr(color + 3 * col, sum / (n * n));
    }
  });
  return out;
}

}  // namespace room_reverb::core::capture_detail
