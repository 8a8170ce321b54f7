#include "room_reverb/vision/cloud_leveling.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <vector>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

namespace {

constexpr std::size_t kMaxPoints = 40000;

// One point per occupied voxel, within range.
std::vector<Eigen::Vector3d> voxelPoints(const PointCloud& cloud, double voxel_m, double max_range_m) {
  std::unordered_set<std::uint64_t> seen;
  std::vector<Eigen::Vector3d> points;
  const double range2 = max_range_m * max_range_m;
  for (const CloudPoint& c : cloud.points) {
    const Eigen::Vector3d p = c.p.cast<double>();
    if (p.squaredNorm() > range2) continue;
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const auto cell = static_cast<std::int64_t>(std::floor(p[a] / voxel_m)) + (1 << 20);
      key = (key << 21) | (static_cast<std::uint64_t>(cell) & 0x1fffff);
    }
    if (seen.insert(key).second) points.push_back(p);
  }
  // An even subsample is enough for a histogram's sharpness, and bounds the search's cost.
  const std::size_t stride = points.size() / kMaxPoints + 1;
  std::vector<Eigen::Vector3d> kept;
  for (std::size_t i = 0; i < points.size(); i += stride) kept.push_back(points[i]);
  return kept;
}

// Rotation by `a` about x, then `b` about y: small tilts in both directions.
Eigen::Matrix3d tiltOf(double a, double b) {
  return (Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX())).toRotationMatrix();
}

// Sum of squared counts of the heights after the tilt: largest when the floor and ceiling
// each fall into as few bins as possible.
double sharpness(const std::vector<Eigen::Vector3d>& points, const Eigen::Matrix3d& tilt, double bin_m) {
  const Eigen::RowVector3d up = tilt.row(2);
  std::vector<double> z(points.size());
  double lo = 1e9, hi = -1e9;
  for (std::size_t i = 0; i < points.size(); ++i) {
    z[i] = up.dot(points[i]);
    lo = std::min(lo, z[i]), hi = std::max(hi, z[i]);
  }
  std::vector<double> count(static_cast<std::size_t>((hi - lo) / bin_m) + 1, 0.0);
  for (double v : z) count[static_cast<std::size_t>((v - lo) / bin_m)] += 1.0;
  double sum = 0.0;
  for (double c : count) sum += c * c;
  return sum;
}

}  // namespace

CloudLeveling levelFromCloud(const PointCloud& cloud, const CloudLevelingOptions& options) {
  if (!(options.max_tilt_rad > 0.0 && options.max_tilt_rad < 0.8) || !(options.voxel_size_m > 0.0) ||
      !(options.bin_m > 0.0) || !(options.max_range_m > 0.0)) {
    throw InputError("cloud leveling: max_tilt_rad must be in (0, 0.8) and the sizes positive");
  }
  checkPointCloud(cloud, 1000);
  const std::vector<Eigen::Vector3d> points = voxelPoints(cloud, options.voxel_size_m, options.max_range_m);
  // Coarse to fine: a grid over the whole range, then three grids each a fifth the size
  // around the best so far (about 0.01 degrees at the end).
  double best_a = 0.0, best_b = 0.0;
  const double upright = sharpness(points, Eigen::Matrix3d::Identity(), options.bin_m);
  double best = upright;
  double half = options.max_tilt_rad, step = options.max_tilt_rad / 8.0;
  for (int level = 0; level < 4; ++level) {
    const double centre_a = best_a, centre_b = best_b;
    for (double a = centre_a - half; a <= centre_a + half + 1e-12; a += step) {
      for (double b = centre_b - half; b <= centre_b + half + 1e-12; b += step) {
        if (std::hypot(a, b) > options.max_tilt_rad) continue;
        const double s = sharpness(points, tiltOf(a, b), options.bin_m);
        if (s > best) best = s, best_a = a, best_b = b;
      }
    }
    half = 1.5 * step;
    step /= 5.0;
  }
  CloudLeveling out;
  out.tilt = tiltOf(best_a, best_b);
  out.tilt_rad = std::acos(std::clamp(out.tilt(2, 2), -1.0, 1.0));
  out.sharpness_gain = upright > 0.0 ? best / upright : 1.0;
  return out;
}

}  // namespace room_reverb::core
