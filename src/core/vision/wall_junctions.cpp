#include "wall_junctions.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "room_reverb/vision/equirect.h"

namespace room_reverb::core::layout {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Bilinear colour at continuous pixel coordinates (pixel centres at integer + 0.5), the
// columns wrapping round the seam, the rows clamped at the poles.
cv::Vec3f sampleColor(const cv::Mat& image, double u, double v) {
  const double x = u - 0.5, y = std::clamp(v - 0.5, 0.0, static_cast<double>(image.rows - 1));
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  const int y1 = std::min(y0 + 1, image.rows - 1);
  const auto column = [&](int c) { return ((c % image.cols) + image.cols) % image.cols; };
  const int c0 = column(x0), c1 = column(x0 + 1);
  const cv::Vec3f a = image.at<cv::Vec3f>(y0, c0), b = image.at<cv::Vec3f>(y0, c1);
  const cv::Vec3f c = image.at<cv::Vec3f>(y1, c0), d = image.at<cv::Vec3f>(y1, c1);
  return (a * (1.0 - fx) + b * fx) * (1.0 - fy) + (c * (1.0 - fx) + d * fx) * fy;
}


double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

struct Wall {
  int axis = 0;        // 0: x, 1: y
  double sign = -1.0;  // -1 on the low side
  double lateral_lo = 0.0, lateral_hi = 0.0;
};

Wall wallOf(const AlignedBox& box, int face) {
  Wall w;
  w.axis = face < 4 ? 0 : 1;
  w.sign = face % 2 == 0 ? -1.0 : 1.0;
  w.lateral_lo = w.axis == 0 ? box.y_lo : box.x_lo;
  w.lateral_hi = w.axis == 0 ? box.y_hi : box.x_hi;
  return w;
}

Eigen::Vector3d pointOn(const Wall& w, double distance, double lateral, double z) {
  Eigen::Vector3d p(0.0, 0.0, z);
  p[w.axis] = w.sign * distance;
  p[1 - w.axis] = lateral;
  return p;
}

// The colour step across one junction line at one candidate distance, 0 when too few of
// its samples are usable. Each sample compares the colour 1, 2 .. step_px pixels below the
// line with as far above it; its step is the smallest of those differences along the mean
// step's direction: an edge between two surfaces differs at every offset, a thin line
// (a tile joint one or two pixels from the candidate) at one only. The line's step is the
// median over its samples: the edge of a picture, a window or a shelf across part of a
// far wall, however strong, does not count, while the junction runs the whole width.
double junctionStep(const cv::Mat& image, const EquirectGeometry& g, const Eigen::Isometry3d& camera_from_aligned,
                    const Wall& w, double distance, double z, const JunctionParams& params) {
  const Eigen::Vector3d normal_camera = camera_from_aligned.linear() * pointOn(w, 1.0, 0.0, 0.0).normalized();
  const double width = w.lateral_hi - w.lateral_lo;
  const double lo = w.lateral_lo + params.corner_margin * width;
  const double span = (1.0 - 2.0 * params.corner_margin) * width;
  const double dl = 0.25 * span / params.samples_per_line;
  const double cos_max = std::cos(params.max_off_normal_rad);
  const int offsets = std::max(1, static_cast<int>(params.step_px));
  cv::Vec3d sum(0.0, 0.0, 0.0);
  std::vector<cv::Vec3d> steps;  // offsets per sample, one after the other
  steps.reserve(static_cast<std::size_t>(params.samples_per_line * offsets));
  for (int i = 0; i < params.samples_per_line; ++i) {
    const double lateral = lo + (i + 0.5) * span / params.samples_per_line;
    const Eigen::Vector3d c = camera_from_aligned * pointOn(w, distance, lateral, z);
    if (c.normalized().dot(normal_camera) < cos_max) continue;
    const Eigen::Vector2d q = equirectCoordinates(g, c);
    Eigen::Vector2d t = equirectCoordinates(g, camera_from_aligned * pointOn(w, distance, lateral + dl, z)) -
                        equirectCoordinates(g, camera_from_aligned * pointOn(w, distance, lateral - dl, z));
    if (t.x() > 0.5 * g.width) t.x() -= g.width;  // the pair straddles the seam
    if (t.x() < -0.5 * g.width) t.x() += g.width;
    if (!(t.norm() > 0.0)) continue;
    Eigen::Vector2d n(-t.y(), t.x());
    n.normalize();
    if (n.y() < 0.0) n = -n;  // towards larger v: below the line
    for (int k = 1; k <= offsets; ++k) {
      const cv::Vec3f step = sampleColor(image, q.x() + k * n.x(), q.y() + k * n.y()) -
                             sampleColor(image, q.x() - k * n.x(), q.y() - k * n.y());
      steps.emplace_back(step[0], step[1], step[2]);
      sum += steps.back();
    }
  }
  const std::size_t samples = steps.size() / static_cast<std::size_t>(offsets);
  const double length = cv::norm(sum);
  if (static_cast<int>(samples) < params.samples_per_line / 4 || !(length > 0.0)) return 0.0;
  const cv::Vec3d direction = sum / length;
  std::vector<double> along(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    double smallest = steps[i * offsets].dot(direction);
    for (int k = 1; k < offsets; ++k) smallest = std::min(smallest, steps[i * offsets + static_cast<std::size_t>(k)].dot(direction));
    along[i] = smallest;
  }
  // The step that line_share of the samples reach.
  const auto at = along.begin() + static_cast<std::ptrdiff_t>((1.0 - params.line_share) * static_cast<double>(samples - 1));
  std::nth_element(along.begin(), at, along.end());
  return std::max(0.0, *at);
}

}  // namespace

cv::Mat junctionImage(const cv::Mat& color) {
  cv::Mat image;
  if (color.empty() || color.channels() != 3) return image;
  color.convertTo(image, CV_32FC3);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.7);
  return image;
}

JunctionFit ceilingJunction(const cv::Mat& image, const Eigen::Isometry3d& camera_from_aligned, const AlignedBox& box,
                            int face, const JunctionParams& params) {
  JunctionFit fit;
  if (!box.has_ceiling || face < 2 || face > 5 || image.empty() || image.type() != CV_32FC3) return fit;
  const Wall w = wallOf(box, face);
  const double fitted = std::abs(box.facePosition(face));  // from the rig, the aligned frame's origin
  const double h = box.top_z - camera_from_aligned.inverse().translation().z();  // the camera below the ceiling
  if (!(fitted > 0.0) || !(h > 0.0) || !(w.lateral_hi > w.lateral_lo)) return fit;

  const EquirectGeometry g{image.cols, image.rows};

  const double lo = fitted * (1.0 - params.search_inward), hi = fitted * (1.0 + params.search_outward);
  const double step = std::max(params.position_step_m, (hi - lo) / 4000.0);
  std::vector<double> distances, steps;
  for (double d = lo; d <= hi; d += step) {
    distances.push_back(d);
    steps.push_back(junctionStep(image, g, camera_from_aligned, w, d, box.top_z, params));
  }
  // A step under half a grey level is no step: the floor keeps the contrast finite on
  // clean images, where most candidates' median step is zero.
  const double typical = std::max(median(steps), 0.5);
  if (distances.size() < 3) return fit;
  const std::size_t best = static_cast<std::size_t>(std::max_element(steps.begin(), steps.end()) - steps.begin());
  const double d = distances[best];
  fit.position_m = w.sign * d;
  fit.contrast = steps[best] / typical;
  // The junction's elevation is atan(h / d): one pixel's angle moves it by (d^2 + h^2) / h.
  fit.pixel_m = 2.0 * kPi / g.width * (d * d + h * h) / h;
  // A maximum at either end of the search is a step still rising (or falling) past it,
  // not a line found.
  const bool interior = best >= 2 && best + 2 < distances.size();
  fit.found = interior && fit.contrast >= params.min_contrast;
  return fit;
}

bool raysMeetJunction(const std::vector<WeightedPoint>& raw, const AlignedBox& box, int face, double position_m,
                      bool outwards, double camera_z, double band_m, double tolerance_m, const JunctionParams& params,
                      double max_off_share, int min_points) {
  const Wall w = wallOf(box, face);
  const double d = std::abs(position_m);
  const double width = w.lateral_hi - w.lateral_lo;
  const double lateral_lo = w.lateral_lo + params.corner_margin * width, lateral_hi = w.lateral_hi - params.corner_margin * width;
  int on_rays = 0, off = 0;
  for (const WeightedPoint& point : raw) {
    const double t = w.sign * point.p[w.axis];  // along the wall's outward normal
    if (!(t > 0.0)) continue;
    // Where the ray from the camera through the point meets the wall's plane.
    const double scale = d / t;
    const double lateral = scale * point.p[1 - w.axis];
    const double z = camera_z + scale * (point.p.z() - camera_z);
    if (lateral < lateral_lo || lateral > lateral_hi || z >= box.top_z || z < box.top_z - band_m) continue;
    ++on_rays;
    if (outwards ? t < d - tolerance_m : t > d + tolerance_m) ++off;
  }
  return on_rays < min_points || off < max_off_share * on_rays;
}

}  // namespace room_reverb::core::layout
