#include "manhattan_frame.h"

#include <cmath>
#include <vector>

#include "room_reverb/common/parallel_rows.h"

namespace room_reverb::core::layout {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kQuarter = 0.5 * kPi;

double degrees(double d) { return d * kPi / 180.0; }

// Sum of squared counts of the two axis histograms at one yaw. Each point is split
// linearly between its two nearest bins so the score changes smoothly with the yaw and a
// sub-bin refinement can follow it.
class SharpnessScore {
 public:
  SharpnessScore(const std::vector<Eigen::Vector2d>& points, double bin_m) : points_(points), inv_bin_(1.0 / bin_m) {
    double reach = 0.0;
    for (const auto& p : points) reach = std::max(reach, p.norm());
    offset_ = reach * inv_bin_ + 2.0;
    bins_ = static_cast<std::size_t>(2.0 * offset_) + 2;
  }

  // Thread-safe: each call has its own histograms.
  double operator()(double yaw) const {
    std::vector<double> hx(bins_, 0.0), hy(bins_, 0.0);
    const double c = std::cos(yaw), s = std::sin(yaw);
    for (const auto& p : points_) {
      splat(hx, (c * p.x() + s * p.y()) * inv_bin_ + offset_);
      splat(hy, (-s * p.x() + c * p.y()) * inv_bin_ + offset_);
    }
    double score = 0.0;
    for (std::size_t i = 0; i < bins_; ++i) score += hx[i] * hx[i] + hy[i] * hy[i];
    return score;
  }

  // The score at each yaw, the yaws spread over the cores (a room's plan holds 10^5
  // points and the search scores it at over a hundred yaws).
  std::vector<double> at(const std::vector<double>& yaws) const {
    std::vector<double> scores(yaws.size());
    forEachRow(static_cast<int>(yaws.size()), 0, [&](int k) { scores[static_cast<std::size_t>(k)] = (*this)(yaws[static_cast<std::size_t>(k)]); });
    return scores;
  }

 private:
  static void splat(std::vector<double>& h, double at) {
    const auto i = static_cast<std::size_t>(at);
    const double f = at - static_cast<double>(i);
    h[i] += 1.0 - f;
    h[i + 1] += f;
  }

  const std::vector<Eigen::Vector2d>& points_;
  double inv_bin_;
  double offset_ = 0.0;
  std::size_t bins_ = 0;
};

}  // namespace

double wrapQuarterTurn(double angle_rad) {
  return angle_rad - kQuarter * std::floor((angle_rad + 0.5 * kQuarter) / kQuarter);
}

double sharpestPlanYaw(const std::vector<Eigen::Vector2d>& plan_points, double bin_m) {
  if (plan_points.empty()) return 0.0;
  const SharpnessScore score(plan_points, bin_m);
  // Coarse: every degree over the quarter turn (the score has the 90-degree period; a
  // wall 10 m long blurs by 17 cm at half a degree off, so the peak is degrees wide).
  // Every fourth point is enough to place a peak that wide: the fine search below, on all
  // of them, reaches 1.2 degrees either side of it.
  constexpr std::size_t kCoarseStride = 4;
  std::vector<Eigen::Vector2d> sparse;
  for (std::size_t i = 0; i < plan_points.size(); i += kCoarseStride) sparse.push_back(plan_points[i]);
  const SharpnessScore sparse_score(sparse, bin_m);
  const double coarse_step = degrees(1.0);
  std::vector<double> coarse_yaws;
  for (double yaw = -0.5 * kQuarter; yaw < 0.5 * kQuarter; yaw += coarse_step) coarse_yaws.push_back(yaw);
  const std::vector<double> coarse = sparse_score.at(coarse_yaws);
  double best_yaw = -0.5 * kQuarter, best = -1.0;
  for (std::size_t k = 0; k < coarse.size(); ++k) {
    if (coarse[k] > best) best = coarse[k], best_yaw = coarse_yaws[k];
  }
  // Fine: 0.1 degree steps around it, then the vertex of a parabola through the best
  // three, which places the peak between steps.
  const double fine_step = degrees(0.1);
  const int reach = 12;
  std::vector<double> fine_yaws;
  for (int k = -reach; k <= reach; ++k) fine_yaws.push_back(best_yaw + k * fine_step);
  const std::vector<double> fine = score.at(fine_yaws);
  int arg = 0;  // the first of equal maxima
  for (int k = 1; k <= 2 * reach; ++k) {
    if (fine[static_cast<std::size_t>(k)] > fine[static_cast<std::size_t>(arg)]) arg = k;
  }
  double yaw = best_yaw + (arg - reach) * fine_step;
  if (arg > 0 && arg < 2 * reach) {
    const double a = fine[arg - 1], b = fine[arg], c = fine[arg + 1];
    const double curvature = a - 2.0 * b + c;
    if (curvature < 0.0) yaw += 0.5 * (a - c) / curvature * fine_step;
  }
  return wrapQuarterTurn(yaw);
}

double refineYawFromWalls(double yaw_rad, const std::vector<WallPoints>& walls) {
  double weighted_offset = 0.0, total_weight = 0.0;
  for (const WallPoints& wall : walls) {
    std::vector<Eigen::Vector2d> pts = wall.plan;
    double offset = 0.0, weight = 0.0;
    for (int pass = 0; pass < 2; ++pass) {
      if (pts.size() < 10) break;
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for (const auto& p : pts) mean += p;
      mean /= static_cast<double>(pts.size());
      Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
      for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
      cov /= static_cast<double>(pts.size());
      // Principal axes of the 2x2 covariance in closed form.
      const double half_diff = 0.5 * (cov(0, 0) - cov(1, 1));
      const double radius = std::hypot(half_diff, cov(0, 1));
      const double mean_var = 0.5 * (cov(0, 0) + cov(1, 1));
      const double var_along = mean_var + radius, var_across = std::max(mean_var - radius, 1e-12);
      const double direction = 0.5 * std::atan2(2.0 * cov(0, 1), cov(0, 0) - cov(1, 1));
      const Eigen::Vector2d across(-std::sin(direction), std::cos(direction));
      const double spread_across = std::sqrt(var_across);
      // The wall's direction, as an offset from the current yaw modulo 90 degrees.
      offset = wrapQuarterTurn(direction - yaw_rad);
      weight = static_cast<double>(pts.size()) * var_along / var_across;
      std::vector<Eigen::Vector2d> kept;
      for (const auto& p : pts) {
        if (std::abs(across.dot(p - mean)) <= 3.0 * spread_across) kept.push_back(p);
      }
      pts.swap(kept);
    }
    // A wall whose fit disagrees with the coarse yaw by more than a few degrees is a
    // furniture face or clutter, not evidence about the walls.
    if (weight > 0.0 && std::abs(offset) < degrees(3.0)) {
      weighted_offset += weight * offset;
      total_weight += weight;
    }
  }
  if (total_weight <= 0.0) return yaw_rad;
  return wrapQuarterTurn(yaw_rad + weighted_offset / total_weight);
}

}  // namespace room_reverb::core::layout
