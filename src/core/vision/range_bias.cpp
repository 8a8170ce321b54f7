#include "room_reverb/vision/range_bias.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "cell_index.h"
#include "norm_standard_error.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

namespace {

constexpr std::size_t kMaxPoints = 40000;
constexpr std::size_t kMaxSample = 200000;
constexpr double kSettled = 2e-5;  // rad: a fiftieth of the smallest offset corrected

// A point as the top camera sees it: range and the angle from the baseline's up direction.
struct TopRay {
  double range = 0.0, polar = 0.0, azimuth = 0.0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit, rig frame
  bool level_surface = false;  // its neighbourhood is a horizontal surface (floor, ceiling, a top)
};

TopRay topRay(const Eigen::Vector3d& p, const Eigen::Vector3d& top) {
  TopRay ray;
  const Eigen::Vector3d v = p - top;
  ray.range = v.norm();
  if (ray.range > 0.0) {
    ray.direction = v / ray.range;
    ray.polar = std::acos(std::clamp(ray.direction.z(), -1.0, 1.0));
    ray.azimuth = std::atan2(ray.direction.y(), ray.direction.x());
  }
  return ray;
}

// The disparity of a point `range` from the top camera, its direction's polar angle given
// as the baseline times its sine and cosine: the angle at the point in the triangle of
// the two cameras and the point.
double disparityAt(double range, double b_sin, double b_cos) { return std::atan2(b_sin, range + b_cos); }

bool offPoles(double polar, double min_polar) { return polar >= min_polar && polar <= M_PI - min_polar; }

Eigen::Vector3i cellOf(const Eigen::Vector3d& p, double size) { return (p / size).array().floor().cast<int>(); }

// Marks the points whose neighbours within neighbourhood_m lie on a horizontal surface:
// the smallest principal axis of their spread within max_normal_tilt_rad of up. The walls'
// feet and the furniture's sides, which lie next to the floor at every offset, are not.
void markLevelSurfaces(std::vector<TopRay>& rays, const Eigen::Vector3d& top, const Eigen::RowVector3d& up,
                       const DisparityOffsetOptions& o) {
  const double cell = o.neighbourhood_m;
  // The points sorted by their cell of neighbourhood_m, each cell filed under its first.
  std::vector<Eigen::Vector3d> points(rays.size());
  std::vector<Eigen::Vector3i> cells(rays.size());
  std::vector<std::size_t> order(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    points[i] = top + rays[i].range * rays[i].direction;
    cells[i] = cellOf(points[i], cell);
    order[i] = i;
  }
  const auto less = [&](std::size_t a, std::size_t b) {
    return std::lexicographical_compare(cells[a].data(), cells[a].data() + 3, cells[b].data(), cells[b].data() + 3);
  };
  std::sort(order.begin(), order.end(), less);
  layout::CellIndex first(rays.size());
  for (std::size_t k = 0; k < order.size(); ++k) first.insert(cells[order[k]], static_cast<std::uint32_t>(k));
  const double cos_tilt = std::cos(o.max_normal_tilt_rad);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    int n = 0;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const Eigen::Vector3i c = cells[i] + Eigen::Vector3i(dx, dy, dz);
          for (std::uint32_t k = first.find(c); k < order.size() && cells[order[k]] == c; ++k) {
            const Eigen::Vector3d& q = points[order[k]];
            if ((q - points[i]).squaredNorm() > cell * cell) continue;
            mean += q, second += q * q.transpose(), ++n;
          }
        }
      }
    }
    if (n < 5) continue;
    mean /= n;
    const Eigen::Matrix3d covariance = second / n - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    rays[i].level_surface = std::abs(up.dot(solver.eigenvectors().col(0))) >= cos_tilt;
  }
}

// One point per occupied voxel, off the poles.
std::vector<TopRay> voxelRays(const PointCloud& cloud, const Eigen::Vector3d& top, const DisparityOffsetOptions& o) {
  layout::CellIndex seen;
  std::vector<TopRay> rays;
  for (const CloudPoint& c : cloud.points) {
    const Eigen::Vector3d p = c.p.cast<double>();
    const TopRay ray = topRay(p, top);
    if (!(ray.range > 0.0) || !offPoles(ray.polar, o.min_polar_rad)) continue;
    if (seen.insert(cellOf(p, o.voxel_size_m), static_cast<std::uint32_t>(rays.size())).second) rays.push_back(ray);
  }
  const std::size_t stride = rays.size() / kMaxPoints + 1;
  std::vector<TopRay> kept;
  for (std::size_t i = 0; i < rays.size(); i += stride) kept.push_back(rays[i]);
  return kept;
}

// The height of the densest horizontal layer among `heights` (a histogram of bin_m, each
// height shared between its two nearest bins, summed over 2 reach + 1 bins so that one
// busy bin of noise does not win), refined to the mean of the heights within that window.
double densestHeight(const std::vector<double>& heights, double bin_m, int reach) {
  const auto [lo, hi] = std::minmax_element(heights.begin(), heights.end());
  std::vector<double> count(static_cast<std::size_t>((*hi - *lo) / bin_m) + 2, 0.0);
  for (double v : heights) {
    const double at = (v - *lo) / bin_m;
    const auto bin = static_cast<std::size_t>(at);
    count[bin] += 1.0 - (at - static_cast<double>(bin));
    count[bin + 1] += at - static_cast<double>(bin);
  }
  std::size_t best = 0;
  double held_best = -1.0;
  for (std::size_t centre = 0; centre < count.size(); ++centre) {
    double held = 0.0;
    for (int k = -reach; k <= reach; ++k) {
      const auto bin = static_cast<std::ptrdiff_t>(centre) + k;
      if (bin >= 0 && bin < static_cast<std::ptrdiff_t>(count.size())) held += count[static_cast<std::size_t>(bin)];
    }
    if (held > held_best) held_best = held, best = centre;
  }
  const double mode = *lo + bin_m * static_cast<double>(best);
  double sum = 0.0;
  int n = 0;
  for (double v : heights) {
    if (std::abs(v - mode) <= bin_m * (reach + 0.5)) sum += v, ++n;
  }
  return n > 0 ? sum / n : mode;
}

}  // namespace

double rangeWithoutDisparityOffset(double range_m, double polar_rad, double baseline_m, double offset_rad) {
  // The triangle of the two cameras and the point: the angle at the point is the
  // disparity d, the bottom camera sees the point at polar angle polar - d, and by the law
  // of sines range / sin(polar - d) = baseline / sin(d).
  const double disparity = disparityAt(range_m, baseline_m * std::sin(polar_rad), baseline_m * std::cos(polar_rad));
  const double corrected = disparity - offset_rad;
  if (!(corrected > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return baseline_m * std::sin(polar_rad - corrected) / std::sin(corrected);
}

namespace {

// The fit's parameters: the offset's constant part, the floor's and the ceiling's heights
// from the top camera (indexed by the plane, 1 and 2), the offset's cos and sin parts, and
// the planes' tilt against `level` along its x and y (their normal up + x ex + y ey).
enum Parameter { kConstant = 0, kFloor = 1, kCeiling = 2, kCos = 3, kSin = 4, kTiltX = 5, kTiltY = 6, kParameters = 7 };
using Vector7 = Eigen::Matrix<double, kParameters, 1>;
using Matrix7 = Eigen::Matrix<double, kParameters, kParameters>;

double offsetAt(const Vector7& x, double cos_az, double sin_az) {
  return x[kConstant] + x[kCos] * cos_az + x[kSin] * sin_az;
}

// The rays of the floor and the ceiling of one pass, with what the fit needs of each.
struct PlaneRays {
  std::vector<int> plane;  // 1 floor, 2 ceiling
  std::vector<double> rho, measured, along, across_x, across_y, cos_az, sin_az, b_sin, b_cos;
  Vector7 start = Vector7::Zero();  // no offset, no tilt and the planes' first heights
  bool has[3] = {false, false, false};
};

// The rays with the offset `x` takes out of their ranges: which of them lie on the floor
// and the ceiling, how far out and the planes' first heights are judged on the cloud as
// corrected so far, since judged on the bent cloud the choice would follow the bend, and
// the estimate with it.
PlaneRays planeRays(std::vector<TopRay> rays, const Vector7& x, double baseline_m, const Eigen::Matrix3d& level,
                    const DisparityOffsetOptions& options) {
  const Eigen::Vector3d top(0.0, 0.0, 0.5 * baseline_m);
  const Eigen::RowVector3d up = level.row(2);
  for (TopRay& ray : rays) {
    const double offset = offsetAt(x, std::cos(ray.azimuth), std::sin(ray.azimuth));
    const double range = rangeWithoutDisparityOffset(ray.range, ray.polar, baseline_m, offset);
    ray.range = std::isfinite(range) ? range : 0.0;
  }
  rays.erase(std::remove_if(rays.begin(), rays.end(), [](const TopRay& ray) { return !(ray.range > 0.0); }), rays.end());
  PlaneRays out;
  std::vector<double> near_floor, near_ceiling;
  for (const TopRay& ray : rays) {
    const Eigen::Vector3d q = top + ray.range * ray.direction;
    const double z = up.dot(q);
    const int plane = z < -options.clear_m ? 1 : (z > options.clear_m ? 2 : 0);
    const double along = up.dot(ray.direction);
    if (plane == 0 || !ray.level_surface || std::abs(along) < 1e-6) continue;
    const double rho = std::sqrt(std::max(0.0, q.squaredNorm() - z * z));
    // The planes' first heights from the points near the rig, which any offset bends least.
    if (rho < options.near_m) (plane == 1 ? near_floor : near_ceiling).push_back(z);
    out.plane.push_back(plane);
    out.rho.push_back(rho);
    out.along.push_back(along);
    out.across_x.push_back(level.row(0).dot(ray.direction));
    out.across_y.push_back(level.row(1).dot(ray.direction));
    out.cos_az.push_back(std::cos(ray.azimuth));
    out.sin_az.push_back(std::sin(ray.azimuth));
    out.b_sin.push_back(baseline_m * std::sin(ray.polar));
    out.b_cos.push_back(baseline_m * std::cos(ray.polar));
    out.measured.push_back(disparityAt(ray.range, out.b_sin.back(), out.b_cos.back()));
  }
  out.has[1] = !near_floor.empty(), out.has[2] = !near_ceiling.empty();
  if (out.has[1]) out.start[kFloor] = densestHeight(near_floor, options.bin_m, 2);
  if (out.has[2]) out.start[kCeiling] = densestHeight(near_ceiling, options.bin_m, 2);
  // Heights are of the levelled frame about the rig's centre; the rays start at the top
  // camera, up.dot(top) above it.
  out.start[kFloor] -= up.dot(top), out.start[kCeiling] -= up.dot(top);
  return out;
}

struct OffsetFit {
  Vector7 x = Vector7::Zero();
  Matrix7 covariance = Matrix7::Zero();
  bool fitted = false;  // points enough, and the normal equations solvable
};

// The parameters marked `free` fitted to the rays from `start` (the others held); the
// planes whose heights are not free are left out. Each point's measured disparity
// against the disparity its ray has where it meets its plane: their difference is the
// offset plus the matcher's noise, with the noise in the measurement alone (a fit of
// heights would put the noise into the slope as well and favour the points read short).
// What stands on the floor or hangs from the ceiling is ranged short of the plane, with a
// disparity too large: it only ever adds residuals above zero. So the residuals' spread
// is taken from those below zero alone (1.48 median absolute deviations), and a point
// counts within max_residual_scales of it either side, fully within huber_scales.
// Gauss-Newton, grown outwards from the rig by grow_m every other iteration, so that the
// far points, which tell the offset from the planes' heights, join a fit already near
// them.
OffsetFit fitDisparityOffset(const PlaneRays& r, const DisparityOffsetOptions& options,
                             const std::array<bool, kParameters>& free, const Vector7& start) {
  OffsetFit out;
  const bool planes[3] = {false, r.has[1] && free[kFloor], r.has[2] && free[kCeiling]};
  if (r.plane.size() < 1000 || !(planes[1] || planes[2])) return out;
  Vector7 x = start;
  Matrix7 normal = Matrix7::Zero();
  double residual = 0.0, scale = options.disparity_noise_rad;
  std::size_t used = 0;
  std::vector<double> residuals;
  constexpr int kSteps = 10, kIterationsPerStep = 2;
  for (int iteration = 0; iteration < kSteps * kIterationsPerStep; ++iteration) {
    const int step = iteration / kIterationsPerStep;
    const double reach = step + 1 < kSteps ? options.near_m + options.grow_m * step
                                           : std::numeric_limits<double>::infinity();
    normal.setZero();
    Vector7 gradient = Vector7::Zero();
    residual = 0.0;
    used = 0;
    residuals.clear();
    for (std::size_t i = 0; i < r.plane.size(); ++i) {
      const int k = r.plane[i];
      if (!planes[k] || r.rho[i] > reach) continue;
      const double along = r.along[i] + x[kTiltX] * r.across_x[i] + x[kTiltY] * r.across_y[i];
      const double to_plane = x[k] / along;
      if (!(to_plane > 0.0)) continue;
      const double expected = disparityAt(to_plane, r.b_sin[i], r.b_cos[i]);
      // Far points are left out by where their plane is, not by their own range: cut by
      // the measured disparity, the far points read long would go and those read short
      // stay, which biases the offset up. Beyond this a point's disparity could be
      // corrected through zero by an offset searched.
      if (expected < 3.0 * options.max_offset_rad) continue;
      const double e = r.measured[i] - offsetAt(x, r.cos_az[i], r.sin_az[i]) - expected;
      if (std::abs(e) > options.max_residual_scales * scale) continue;
      if (e < 0.0) residuals.push_back(-e);
      // d(disparity)/d(range along the ray), less its sign.
      const double xx = to_plane + r.b_cos[i];
      const double slope = r.b_sin[i] / (xx * xx + r.b_sin[i] * r.b_sin[i]);
      Vector7 j = Vector7::Zero();
      j[kConstant] = -1.0;
      j[kCos] = -r.cos_az[i];
      j[kSin] = -r.sin_az[i];
      j[k] = slope / along;
      j[kTiltX] = -slope * x[k] * r.across_x[i] / (along * along);
      j[kTiltY] = -slope * x[k] * r.across_y[i] / (along * along);
      for (int p = 0; p < kParameters; ++p) {
        if (!free[static_cast<std::size_t>(p)]) j[p] = 0.0;
      }
      const double w = std::abs(e) <= options.huber_scales * scale ? 1.0 : options.huber_scales * scale / std::abs(e);
      normal += w * j * j.transpose();
      gradient += w * j * e;
      residual += w * e * e;
      ++used;
    }
    for (int p = 0; p < kParameters; ++p) {
      // A held parameter, or an absent plane, stays put.
      if (normal(p, p) == 0.0) normal(p, p) = 1.0;
    }
    const Eigen::FullPivLU<Matrix7> lu(normal);
    if (used < 1000 || lu.rank() < kParameters) return out;
    x += lu.solve(-gradient);
    x[kConstant] = std::clamp(x[kConstant], -options.max_offset_rad, options.max_offset_rad);
    if (residuals.empty()) break;
    std::nth_element(residuals.begin(), residuals.begin() + static_cast<std::ptrdiff_t>(residuals.size() / 2),
                     residuals.end());
    scale = std::max(1e-5, 1.4826 * residuals[residuals.size() / 2]);
  }
  out.x = x;
  // The standard errors from the fit's own scatter: the weighted residuals' variance
  // times the normal matrix's inverse.
  int count = 0;
  for (bool f : free) count += f ? 1 : 0;
  const double variance = residual / static_cast<double>(used - static_cast<std::size_t>(count));
  out.covariance = normal.inverse() * variance;
  out.fitted = true;
  return out;
}

}  // namespace

DisparityOffset estimateDisparityOffset(const PointCloud& cloud, double baseline_m, const Eigen::Matrix3d& level,
                                        const DisparityOffsetOptions& options) {
  if (!(baseline_m > 0.0) || !std::isfinite(baseline_m)) throw InputError("range bias: the baseline must be positive");
  if (!(options.max_offset_rad > 0.0 && options.max_offset_rad < 0.1) || !(options.voxel_size_m > 0.0) ||
      !(options.bin_m > 0.0) || !(options.near_m > 0.0) || !(options.grow_m > 0.0) || !(options.disparity_noise_rad > 0.0) || !(options.huber_scales > 0.0) || !(options.max_residual_scales > 0.0) ||
      !(options.min_offset_rad >= 0.0) || !(options.min_azimuth_offset_rad >= 0.0) ||
      !(options.min_significance >= 0.0) ||
      !(options.min_polar_rad >= 0.0 && options.min_polar_rad < 1.5)) {
    throw InputError("range bias: max_offset_rad must be in (0, 0.1), min_polar_rad in [0, 1.5) and the sizes, noise "
                     "and thresholds positive");
  }
  checkPointCloud(cloud, 1000);
  // Which points lie on the floor and the ceiling is judged on the cloud as corrected so
  // far: judged on the bent cloud, the choice would follow the bend, and the estimate
  // with it. The fit is repeated on the corrected cloud, at most three times, until it
  // changes by less than kSettled. An even subsample bounds the cost of the passes (a 2048 x 1024 pair gives a million
  // points, the fit keeps at most 40 000 voxels of them).
  PointCloud sample;
  const std::size_t stride = cloud.points.size() / kMaxSample + 1;
  sample.points.reserve(cloud.points.size() / stride + 1);
  for (std::size_t i = 0; i < cloud.points.size(); i += stride) sample.points.push_back(cloud.points[i]);
  // The voxels and their surfaces' orientation once: an offset bends a 15 cm patch by a
  // small fraction of a degree.
  const Eigen::Vector3d top(0.0, 0.0, 0.5 * baseline_m);
  std::vector<TopRay> voxels = voxelRays(sample, top, options);
  markLevelSurfaces(voxels, top, level.row(2), options);
  PlaneRays rays = planeRays(voxels, Vector7::Zero(), baseline_m, level, options);
  // The part with the azimuth only where both planes are seen: with one, an offset that
  // goes with the azimuth bends it as its tilt does.
  const bool both_planes = rays.has[1] && rays.has[2];
  const std::array<bool, kParameters> joint{true, true, true, both_planes, both_planes, true, true};
  OffsetFit fit = fitDisparityOffset(rays, options, joint, rays.start);
  Vector7 total = fit.x;  // the offsets found so far; the heights and the tilt of the last pass
  for (int pass = 1; pass < 3 && fit.fitted; ++pass) {
    rays = planeRays(voxels, total, baseline_m, level, options);
    Vector7 start = rays.start;
    start[kTiltX] = total[kTiltX], start[kTiltY] = total[kTiltY];
    const OffsetFit more = fitDisparityOffset(rays, options, joint, start);
    if (!more.fitted) break;
    fit = more;
    const Eigen::Vector3d step(more.x[kConstant], more.x[kCos], more.x[kSin]);
    for (int p : {kConstant, kCos, kSin}) total[p] += more.x[p];
    total[kConstant] = std::clamp(total[kConstant], -options.max_offset_rad, options.max_offset_rad);
    for (int p : {kFloor, kCeiling, kTiltX, kTiltY}) total[p] = more.x[p];
    if (step.cwiseAbs().maxCoeff() < kSettled) break;
  }
  DisparityOffset out;
  out.standard_error_rad = std::numeric_limits<double>::infinity();
  out.azimuth_standard_error_rad = std::numeric_limits<double>::infinity();
  if (!fit.fitted) return out;
  out.offset_rad = total[kConstant];
  out.standard_error_rad = std::sqrt(std::max(0.0, fit.covariance(kConstant, kConstant)));
  out.cos_rad = total[kCos];
  out.sin_rad = total[kSin];
  const Eigen::Matrix2d azimuth_covariance = fit.covariance.block<2, 2>(kCos, kCos);
  const Eigen::Vector2d azimuth(total[kCos], total[kSin]);
  out.azimuth_standard_error_rad = both_planes ? vision_detail::normStandardError<2>(azimuth, azimuth_covariance) : 0.0;
  out.plane_tilt_rad = std::atan(std::hypot(total[kTiltX], total[kTiltY]));
  // An offset bends the floor and the ceiling alike; where each alone asks for a different
  // one, what bends them is not the offset (a matcher's bias on one of them, a floor that
  // is not flat), and nothing is corrected. Each alone holds the planes' tilt the two
  // together found.
  Vector7 held = rays.start;
  held[kTiltX] = fit.x[kTiltX], held[kTiltY] = fit.x[kTiltY];
  const OffsetFit floor =
      fitDisparityOffset(rays, options, {true, true, false, both_planes, both_planes, false, false}, held);
  const OffsetFit ceiling =
      fitDisparityOffset(rays, options, {true, false, true, both_planes, both_planes, false, false}, held);
  out.floor_fitted = floor.fitted;
  out.ceiling_fitted = ceiling.fitted;
  out.floor_offset_rad = total[kConstant] + floor.x[kConstant];
  out.ceiling_offset_rad = total[kConstant] + ceiling.x[kConstant];
  out.floor_azimuth = Eigen::Vector2d(total[kCos] + floor.x[kCos], total[kSin] + floor.x[kSin]);
  out.ceiling_azimuth = Eigen::Vector2d(total[kCos] + ceiling.x[kCos], total[kSin] + ceiling.x[kSin]);
  const bool both = out.floor_fitted && out.ceiling_fitted;
  const auto agree = [&](double difference, double size) {
    return difference <= std::max(options.max_disagreement_rad, options.max_disagreement_share * size);
  };
  out.planes_agree = !both || agree(std::abs(out.floor_offset_rad - out.ceiling_offset_rad), std::abs(out.offset_rad));
  out.applied = std::abs(out.offset_rad) >= options.min_offset_rad &&
                std::abs(out.offset_rad) >= options.min_significance * out.standard_error_rad &&
                std::abs(out.offset_rad) < options.max_offset_rad && out.planes_agree;
  const double amplitude = std::hypot(out.cos_rad, out.sin_rad);
  out.azimuth_planes_agree = both && agree((out.floor_azimuth - out.ceiling_azimuth).norm(), amplitude);
  out.azimuth_applied = both_planes && both && amplitude >= options.min_azimuth_offset_rad &&
                        amplitude >= options.min_significance * out.azimuth_standard_error_rad &&
                        amplitude < options.max_offset_rad && out.azimuth_planes_agree;
  return out;
}

double DisparityOffset::correctionAt(double azimuth_rad) const {
  return (applied ? offset_rad : 0.0) +
         (azimuth_applied ? cos_rad * std::cos(azimuth_rad) + sin_rad * std::sin(azimuth_rad) : 0.0);
}

PointCloud removeDisparityOffset(const PointCloud& cloud, double baseline_m, double offset_rad, double min_polar_rad) {
  DisparityOffset constant;
  constant.offset_rad = offset_rad;
  constant.applied = true;
  return removeDisparityOffset(cloud, baseline_m, constant, min_polar_rad);
}

PointCloud removeDisparityOffset(const PointCloud& cloud, double baseline_m, const DisparityOffset& offset,
                                 double min_polar_rad) {
  PointCloud out = cloud;
  const Eigen::Vector3d top(0.0, 0.0, 0.5 * baseline_m);
  for (CloudPoint& c : out.points) {
    const TopRay ray = topRay(c.p.cast<double>(), top);
    if (!(ray.range > 0.0) || !offPoles(ray.polar, min_polar_rad)) continue;
    const double range =
        rangeWithoutDisparityOffset(ray.range, ray.polar, baseline_m, offset.correctionAt(ray.azimuth));
    if (std::isfinite(range)) c.p = (top + range * ray.direction).cast<float>();
  }
  return out;
}

}  // namespace room_reverb::core
