#include "room_reverb/vision/range_bias.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Eigenvalues>

#include "cell_index.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

namespace {

constexpr std::size_t kMaxPoints = 40000;
constexpr std::size_t kMaxSample = 200000;

// A point as the top camera sees it: range and the angle from the baseline's up direction.
struct TopRay {
  double range = 0.0, polar = 0.0;
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
  }
  return ray;
}

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
std::vector<TopRay> voxelRays(const PointCloud& cloud, const Eigen::Vector3d& top,
                              const Eigen::RowVector3d& up, const DisparityOffsetOptions& o) {
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
  markLevelSurfaces(kept, top, up, o);
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
  const double disparity = std::atan2(baseline_m * std::sin(polar_rad), range_m + baseline_m * std::cos(polar_rad));
  const double corrected = disparity - offset_rad;
  if (!(corrected > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return baseline_m * std::sin(polar_rad - corrected) / std::sin(corrected);
}

namespace {

// One fit of the offset on the cloud as it stands; `only` 1 or 2 fits the floor or the
// ceiling alone, 0 both.
DisparityOffset fitDisparityOffset(const PointCloud& cloud, double baseline_m, const Eigen::Matrix3d& level,
                                   const DisparityOffsetOptions& options, int only = 0) {
  const Eigen::Vector3d top(0.0, 0.0, 0.5 * baseline_m);
  const std::vector<TopRay> rays = voxelRays(cloud, top, level.row(2), options);
  DisparityOffset out;
  out.points = rays.size();
  out.standard_error_rad = std::numeric_limits<double>::infinity();
  if (rays.size() < 1000) return out;
  // The floor and the ceiling as two horizontal planes, heights h[1] and h[2], sharing
  // the offset h[0]: a least-squares fit of the points' levelled heights to their planes,
  // each weighted by its expected noise (range_noise of its range along the ray, at least
  // a centimetre), a point taken within band_m and three times that noise of its plane
  // (the walls' feet, the tables and the hanging lights fall out). Gauss-Newton, the
  // offset's effect on a height smooth and nearly linear over the range searched.
  const Eigen::RowVector3d up = level.row(2);
  std::vector<int> plane(rays.size(), 0);  // 1 floor, 2 ceiling, 0 neither
  std::vector<double> near_floor, near_ceiling;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector3d q = top + rays[i].range * rays[i].direction;
    const double z = up.dot(q);
    if (z < -options.clear_m) plane[i] = 1;
    if (z > options.clear_m) plane[i] = 2;
    // The planes' first heights from the points near the rig, which any offset bends least.
    const double rho = std::sqrt(std::max(0.0, q.squaredNorm() - z * z));
    if (rho < options.near_m && plane[i] == 1) near_floor.push_back(z);
    if (rho < options.near_m && plane[i] == 2) near_ceiling.push_back(z);
  }
  Eigen::Vector3d h(0.0, near_floor.empty() ? 0.0 : densestHeight(near_floor, options.bin_m, 2),
                    near_ceiling.empty() ? 0.0 : densestHeight(near_ceiling, options.bin_m, 2));
  const bool planes[3] = {false, !near_floor.empty() && only != 2, !near_ceiling.empty() && only != 1};
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  double residual = 0.0, weight_sum = 0.0;
  std::size_t used = 0;
  std::vector<double> rho(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector3d q = top + rays[i].range * rays[i].direction;
    const double z = up.dot(q);
    rho[i] = std::sqrt(std::max(0.0, q.squaredNorm() - z * z));
  }
  // Each point's measured disparity against the disparity its ray would have where it
  // meets its plane: their difference is the offset plus the stereo's noise, linear in
  // the offset, with the noise in the measurement alone (a fit of heights would put the
  // noise into the slope as well and favour the points read short). What stands on the
  // floor or hangs from the ceiling is ranged short of the plane, with a disparity too
  // large: it only ever adds residuals above zero. So the residuals' spread is taken from
  // those below zero alone (1.48 median absolute deviations), and a point counts within
  // max_residual_scales of it either side, fully within huber_scales.
  const auto disparityOf = [&](double range, double polar) {
    return std::atan2(baseline_m * std::sin(polar), range + baseline_m * std::cos(polar));
  };
  std::vector<double> measured(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) measured[i] = disparityOf(rays[i].range, rays[i].polar);
  double scale = options.disparity_noise_rad;
  // Grown outwards from the rig by grow_m every third iteration, so that the far points,
  // which tell the offset from the planes' heights, join a fit already near them.
  const int kSteps = 16, kIterationsPerStep = 3;
  std::vector<double> residuals;
  for (int iteration = 0; iteration < kSteps * kIterationsPerStep; ++iteration) {
    const double reach = options.near_m + options.grow_m * (iteration / kIterationsPerStep);
    normal.setZero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    residual = weight_sum = 0.0;
    used = 0;
    residuals.clear();
    constexpr double kStep = 1e-4;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const int k = plane[i];
      if (k == 0 || !planes[k] || !rays[i].level_surface || rho[i] > reach) continue;
      const double along = up.dot(rays[i].direction);
      if (std::abs(along) < 1e-6) continue;
      const double to_plane = (h[k] - up.dot(top)) / along;
      const double to_plane_up = (h[k] + kStep - up.dot(top)) / along;
      if (!(to_plane > 0.0) || !(to_plane_up > 0.0)) continue;
      const double expected = disparityOf(to_plane, rays[i].polar);
      // Far points are left out by where their plane is, not by their own range: cut by
      // the measured disparity, the far points read long would go and those read short
      // stay, which biases the offset up. Beyond this a point's disparity could be
      // corrected through zero by an offset searched.
      if (expected < 3.0 * options.max_offset_rad) continue;
      const double e = measured[i] - h[0] - expected;
      if (std::abs(e) > options.max_residual_scales * scale) continue;
      if (e < 0.0) residuals.push_back(-e);
      Eigen::Vector3d j = Eigen::Vector3d::Zero();
      j[0] = -1.0;
      j[k] = -(disparityOf(to_plane_up, rays[i].polar) - expected) / kStep;
      const double w = std::abs(e) <= options.huber_scales * scale ? 1.0 : options.huber_scales * scale / std::abs(e);
      normal += w * j * j.transpose();
      gradient += w * j * e;
      residual += w * e * e, weight_sum += w;
      ++used;
    }
    for (int k = 1; k < 3; ++k) {
      if (!planes[k] || normal(k, k) == 0.0) normal(k, k) = 1.0;  // an absent plane stays put
    }
    if (used < 1000 || std::abs(normal.determinant()) < 1e-300) break;
    h += normal.ldlt().solve(-gradient);
    h[0] = std::clamp(h[0], -options.max_offset_rad, options.max_offset_rad);
    if (residuals.empty()) break;
    std::nth_element(residuals.begin(), residuals.begin() + static_cast<std::ptrdiff_t>(residuals.size() / 2),
                     residuals.end());
    scale = std::max(1e-5, 1.4826 * residuals[residuals.size() / 2]);
  }
  out.offset_rad = h[0];
  // The offset's standard error from the fit's own scatter: the weighted residual's
  // variance over that expected from the noise, times the normal matrix's inverse.
  if (used >= 1000 && weight_sum > 0.0) {
    const double variance = residual / static_cast<double>(used - 3);
    out.standard_error_rad = std::sqrt(std::max(0.0, normal.inverse()(0, 0) * variance));
  } else {
    out.standard_error_rad = std::numeric_limits<double>::infinity();
  }
  return out;
}

}  // namespace

DisparityOffset estimateDisparityOffset(const PointCloud& cloud, double baseline_m, const Eigen::Matrix3d& level,
                                        const DisparityOffsetOptions& options) {
  if (!(baseline_m > 0.0) || !std::isfinite(baseline_m)) throw InputError("range bias: the baseline must be positive");
  if (!(options.max_offset_rad > 0.0 && options.max_offset_rad < 0.1) || !(options.voxel_size_m > 0.0) ||
      !(options.bin_m > 0.0) || !(options.near_m > 0.0) || !(options.grow_m > 0.0) || !(options.disparity_noise_rad > 0.0) || !(options.huber_scales > 0.0) || !(options.max_residual_scales > 0.0) ||
      !(options.min_offset_rad >= 0.0) || !(options.min_significance >= 0.0) ||
      !(options.min_polar_rad >= 0.0 && options.min_polar_rad < 1.5)) {
    throw InputError("range bias: max_offset_rad must be in (0, 0.1), min_polar_rad in [0, 1.5) and the sizes, noise "
                     "and thresholds positive");
  }
  checkPointCloud(cloud, 1000);
  // Which points lie on the floor and the ceiling is judged on the cloud as corrected so
  // far: judged on the bent cloud, the choice would follow the bend, and the estimate
  // with it. The fit is repeated on the corrected cloud until its change is below a
  // hundredth of the smallest offset applied.
  // An even subsample bounds the cost of the passes (a 2048 x 1024 pair gives a million
  // points, the fit keeps at most 40 000 voxels of them).
  PointCloud sample;
  const std::size_t stride = cloud.points.size() / kMaxSample + 1;
  sample.points.reserve(cloud.points.size() / stride + 1);
  for (std::size_t i = 0; i < cloud.points.size(); i += stride) sample.points.push_back(cloud.points[i]);
  DisparityOffset total = fitDisparityOffset(sample, baseline_m, level, options);
  for (int pass = 1; pass < 4 && std::isfinite(total.standard_error_rad); ++pass) {
    const DisparityOffset more =
        fitDisparityOffset(removeDisparityOffset(sample, baseline_m, total.offset_rad, options.min_polar_rad), baseline_m,
                           level, options);
    total.offset_rad = std::clamp(total.offset_rad + more.offset_rad, -options.max_offset_rad, options.max_offset_rad);
    total.standard_error_rad = more.standard_error_rad;
    total.points = more.points;
    if (std::abs(more.offset_rad) < 0.01 * std::max(options.min_offset_rad, 1e-5)) break;
  }
  // A disparity offset bends the floor and the ceiling alike; where each alone asks for a
  // different one, what bends them is not the offset (a matcher's bias on one of them, a
  // floor that is not flat), and nothing is corrected.
  const PointCloud corrected = removeDisparityOffset(sample, baseline_m, total.offset_rad, options.min_polar_rad);
  const DisparityOffset floor = fitDisparityOffset(corrected, baseline_m, level, options, 1);
  const DisparityOffset ceiling = fitDisparityOffset(corrected, baseline_m, level, options, 2);
  total.floor_offset_rad = total.offset_rad + floor.offset_rad;
  total.ceiling_offset_rad = total.offset_rad + ceiling.offset_rad;
  const bool both = std::isfinite(floor.standard_error_rad) && std::isfinite(ceiling.standard_error_rad) &&
                    floor.points > 0 && ceiling.points > 0;
  total.planes_agree = !both || std::abs(total.floor_offset_rad - total.ceiling_offset_rad) <=
                                    std::max(options.max_disagreement_rad,
                                             options.max_disagreement_share * std::abs(total.offset_rad));
  total.applied = std::abs(total.offset_rad) >= options.min_offset_rad &&
                  std::abs(total.offset_rad) >= options.min_significance * total.standard_error_rad &&
                  std::abs(total.offset_rad) < options.max_offset_rad && total.planes_agree;
  return total;
}

PointCloud removeDisparityOffset(const PointCloud& cloud, double baseline_m, double offset_rad, double min_polar_rad) {
  PointCloud out = cloud;
  const Eigen::Vector3d top(0.0, 0.0, 0.5 * baseline_m);
  for (CloudPoint& c : out.points) {
    const TopRay ray = topRay(c.p.cast<double>(), top);
    if (!(ray.range > 0.0) || !offPoles(ray.polar, min_polar_rad)) continue;
    const double range = rangeWithoutDisparityOffset(ray.range, ray.polar, baseline_m, offset_rad);
    if (std::isfinite(range)) c.p = (top + range * ray.direction).cast<float>();
  }
  return out;
}

}  // namespace room_reverb::core
