#include "room_reverb/vision/surface_patches.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "room_reverb/vision/room_raycast.h"
#include "room_reverb/common/parallel_rows.h"
#include "room_reverb/vision/equirect.h"
#include "room_reverb/vision/material_features.h"

namespace room_reverb::core::material_detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Downsampled copies of the image for near surfaces: a patch pixel covering several
// image pixels is read from a level where it covers about one, so fine detail does not
// alias into false texture. Level 3 is an eighth of the width.
constexpr int kPyramidLevels = 4;
// Fewer seen pixels than this make a patch too small to show a texture.
constexpr int kMinSeenPixels = 64;

SurfaceRect makeRect(int target, const Eigen::Vector3d& center, const Eigen::Vector3d& normal, const Eigen::Vector3d& v,
                     double half_width, double half_height) {
  SurfaceRect rect;
  rect.target = target;
  rect.center_m = center;
  rect.normal = normal;
  rect.v = v;
  // Right as seen by someone facing the surface with v up, so patches are not mirrored.
  rect.u = v.cross(normal);
  rect.half_width_m = half_width;
  rect.half_height_m = half_height;
  return rect;
}

// How far from a patch point the cast may find the surface and still count it as that
// point [m]: a centimetre and half a percent of the range.
double hitTolerance(double range) { return 0.01 + 0.005 * range; }

struct PatchJob {
  std::size_t rect = 0;
  double s_m = 0.0, t_m = 0.0;  // patch centre on the rectangle
};

// Patch centres covering a length of 2 * half: as many patches as it takes, the overhang
// split evenly at both ends.
std::vector<double> centresAlong(double half, double size) {
  const int count = std::max(1, static_cast<int>(std::ceil(2.0 * half / size - 1e-9)));
  std::vector<double> centres;
  for (int i = 0; i < count; ++i) centres.push_back((i - 0.5 * (count - 1)) * size);
  return centres;
}

class PatchCutter {
 public:
  PatchCutter(const cv::Mat& color, const RoomModel& model, const Eigen::Isometry3d& room_from_camera,
              const PatchSampling& sampling)
      : sampling_(sampling),
        geometry_(makeCaptureGeometry(model, {})),
        camera_(room_from_camera.translation()),
        room_to_camera_(room_from_camera.linear().transpose()),
        equirect_{color.cols, color.rows} {
    pyramid_.push_back(color);
    for (int level = 1; level < kPyramidLevels && pyramid_.back().rows >= 16; ++level) {
      cv::Mat down;
      cv::pyrDown(pyramid_.back(), down);
      pyramid_.push_back(down);
    }
  }

  std::optional<SurfacePatch> cut(const SurfaceRect& rect, double s_centre, double t_centre) const {
    const int n = sampling_.geometry.pixels;
    const double step = sampling_.geometry.size_m / n;
    const double pixel_angle = 2.0 * kPi / equirect_.width;
    cv::Mat map_x(n, n, CV_32FC1, cv::Scalar(0)), map_y(n, n, CV_32FC1, cv::Scalar(0));
    cv::Mat mask(n, n, CV_8UC1, cv::Scalar(0));
    const std::vector<std::size_t> candidates =
        reachableObjects(rect.center_m + s_centre * rect.u + t_centre * rect.v);
    int seen = 0, inside = 0;
    double footprint_sum = 0.0, slant_sum = 0.0;
    for (int row = 0; row < n; ++row) {
      const double t = t_centre + (0.5 * n - row - 0.5) * step;  // row 0 at the top (largest t)
      if (std::abs(t) > rect.half_height_m) continue;
      for (int col = 0; col < n; ++col) {
        const double s = s_centre + (col + 0.5 - 0.5 * n) * step;
        if (std::abs(s) > rect.half_width_m) continue;
        ++inside;
        const Eigen::Vector3d point = rect.center_m + s * rect.u + t * rect.v;
        const Eigen::Vector3d ray = point - camera_;
        const double range = ray.norm();
        if (!(range > 1e-6)) continue;
        const Eigen::Vector3d direction = ray / range;
        const double cos_incidence = -direction.dot(rect.normal);
        if (cos_incidence < sampling_.min_cos_incidence) continue;
        // Seen only if the first thing along the ray is this surface at this point.
        const SurfaceHit hit = castRay(geometry_, camera_, direction, candidates);
        if (hit.sky || hit.object_id != rect.target || std::abs(hit.distance_m - range) > hitTolerance(range)) continue;
        const Eigen::Vector2d uv = equirectCoordinates(equirect_, room_to_camera_ * direction);
        map_x.at<float>(row, col) = static_cast<float>(uv.x());
        map_y.at<float>(row, col) = static_cast<float>(uv.y());
        mask.at<unsigned char>(row, col) = 255;
        ++seen;
        footprint_sum += pixel_angle * range;
        slant_sum += 1.0 / cos_incidence;
      }
    }
    // Coverage counts against the part of the patch on the surface, so the side of a
    // small loudspeaker, smaller than one patch, is still classified when it is in view.
    if (seen < kMinSeenPixels || seen < sampling_.min_coverage * inside) return std::nullopt;
    const double footprint = footprint_sum / seen;  // one image pixel on the surface, face-on [m]
    const double slant = slant_sum / seen;
    SurfacePatch patch;
    patch.target = rect.target;
    patch.s_m = s_centre;
    patch.t_m = t_centre;
    // Across the slanted direction an image pixel covers footprint * slant of the surface.
    patch.source_pixels = sampling_.geometry.size_m / (footprint * slant);
    if (patch.source_pixels < sampling_.min_source_pixels) return std::nullopt;
    patch.area_m2 = seen * step * step;
    patch.mask = mask;

    // The level where one image pixel covers about one patch pixel (geometric mean of the
    // two directions' footprints), never finer than the image.
    const double ratio = step / (footprint * std::sqrt(slant));
    const int top = static_cast<int>(pyramid_.size()) - 1;
    const int level = std::clamp(static_cast<int>(std::floor(std::log2(std::max(ratio, 1.0)))), 0, top);
    const float scale = 1.0f / static_cast<float>(1 << level);
    // Continuous coordinates have pixel centres at +0.5; remap wants them at integers.
    map_x = map_x * scale - 0.5f;
    map_y = map_y * scale - 0.5f;
    cv::remap(pyramid_[static_cast<std::size_t>(level)], patch.bgr, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_WRAP);
    patch.bgr.setTo(cv::Scalar::all(0), ~mask);
    return patch;
  }

 private:
  // The objects a ray to a point of the patch centred at `centre` can meet before it is
  // past the point by the tolerance of the visibility test: the others cannot change what
  // the test finds (room_raycast.h), and most patches have none.
  std::vector<std::size_t> reachableObjects(const Eigen::Vector3d& centre) const {
    const double radius = std::sqrt(0.5) * sampling_.geometry.size_m;  // the patch's half diagonal
    return objectsInReach(geometry_, camera_, centre, radius, hitTolerance((centre - camera_).norm() + radius));
  }

  PatchSampling sampling_;
  CaptureGeometry geometry_;
  Eigen::Vector3d camera_;
  Eigen::Matrix3d room_to_camera_;
  EquirectGeometry equirect_;
  std::vector<cv::Mat> pyramid_;
};

}  // namespace

std::vector<SurfaceRect> modelSurfaceRects(const RoomModel& model) {
  const Eigen::Vector3d size = model.size_m, half = 0.5 * size;
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  std::vector<SurfaceRect> rects;
  rects.push_back(makeRect(0, Eigen::Vector3d(half.x(), half.y(), 0.0), z, y, half.x(), half.y()));
  if (model.has_ceiling) rects.push_back(makeRect(1, Eigen::Vector3d(half.x(), half.y(), size.z()), -z, y, half.x(), half.y()));
  rects.push_back(makeRect(2, Eigen::Vector3d(0.0, half.y(), half.z()), x, z, half.y(), half.z()));
  rects.push_back(makeRect(3, Eigen::Vector3d(size.x(), half.y(), half.z()), -x, z, half.y(), half.z()));
  rects.push_back(makeRect(4, Eigen::Vector3d(half.x(), 0.0, half.z()), y, z, half.x(), half.z()));
  rects.push_back(makeRect(5, Eigen::Vector3d(half.x(), size.y(), half.z()), -y, z, half.x(), half.z()));
  for (std::size_t k = 0; k < model.objects.size(); ++k) {
    const CuboidObject& object = model.objects[k];
    const int target = 6 + static_cast<int>(k);
    const Eigen::Matrix3d yaw = Eigen::AngleAxisd(object.yaw_rad, z).toRotationMatrix();
    const Eigen::Vector3d h = 0.5 * object.size_m, ax = yaw * x, ay = yaw * y;
    for (const double sign : {-1.0, 1.0}) {
      rects.push_back(makeRect(target, object.center_m + sign * h.x() * ax, sign * ax, z, h.y(), h.z()));
      rects.push_back(makeRect(target, object.center_m + sign * h.y() * ay, sign * ay, z, h.x(), h.z()));
    }
    rects.push_back(makeRect(target, object.center_m + h.z() * z, z, ay, h.x(), h.y()));
  }
  return rects;
}

std::vector<SurfacePatch> sampleSurfacePatches(const cv::Mat& color, const RoomModel& model,
                                               const Eigen::Isometry3d& room_from_camera, const PatchSampling& sampling) {
  const std::vector<SurfaceRect> rects = modelSurfaceRects(model);
  const Eigen::Vector3d camera = room_from_camera.translation();
  std::vector<PatchJob> jobs;
  for (std::size_t r = 0; r < rects.size(); ++r) {
    const SurfaceRect& rect = rects[r];
    const double size = sampling.geometry.size_m;
    std::vector<PatchJob> on_rect;
    for (const double t : centresAlong(rect.half_height_m, size)) {
      for (const double s : centresAlong(rect.half_width_m, size)) on_rect.push_back({r, s, t});
    }
    const auto limit = static_cast<std::size_t>(sampling.max_patches_per_rect);
    if (limit > 0 && on_rect.size() > limit) {
      const auto range = [&](const PatchJob& job) { return (rect.center_m + job.s_m * rect.u + job.t_m * rect.v - camera).norm(); };
      std::vector<std::pair<double, std::size_t>> by_range;
      for (std::size_t i = 0; i < on_rect.size(); ++i) by_range.emplace_back(range(on_rect[i]), i);
      std::nth_element(by_range.begin(), by_range.begin() + static_cast<std::ptrdiff_t>(limit), by_range.end());
      std::vector<std::size_t> kept;
      for (std::size_t i = 0; i < limit; ++i) kept.push_back(by_range[i].second);
      std::sort(kept.begin(), kept.end());  // along the rectangle, as without the limit
      for (const std::size_t i : kept) jobs.push_back(on_rect[i]);
    } else {
      jobs.insert(jobs.end(), on_rect.begin(), on_rect.end());
    }
  }
  const PatchCutter cutter(color, model, room_from_camera, sampling);
  std::vector<std::optional<SurfacePatch>> cut(jobs.size());
  forEachRow(static_cast<int>(jobs.size()), sampling.threads, [&](int j) {
    const PatchJob& job = jobs[static_cast<std::size_t>(j)];
    cut[static_cast<std::size_t>(j)] = cutter.cut(rects[job.rect], job.s_m, job.t_m);
  });
  std::vector<SurfacePatch> patches;
  for (auto& patch : cut) {
    if (patch) patches.push_back(std::move(*patch));
  }
  return patches;
}

cv::Mat patchFeatures(const std::vector<const SurfacePatch*>& patches, int threads) {
  cv::Mat features(static_cast<int>(patches.size()), kMaterialFeatureLength, CV_32F);
  forEachRow(features.rows, threads, [&](int i) {
    const SurfacePatch& patch = *patches[static_cast<std::size_t>(i)];
    materialFeatures(patch.bgr, patch.mask).copyTo(features.row(i));
  });
  return features;
}

}  // namespace room_reverb::core::material_detail
