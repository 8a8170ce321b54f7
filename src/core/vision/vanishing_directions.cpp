#include "vanishing_directions.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "room_reverb/common/parallel_rows.h"

namespace room_reverb::core::vision_detail {
namespace {

// Below this, two great circles (or a circle and a direction) are too close to parallel
// to define the direction they share.
constexpr double kMinCrossNorm = 0.05;

// The direction (column) whose |n . v| is smallest.
int nearestDirection(const Eigen::Matrix3d& V, const Eigen::Vector3d& n, double* residual) {
  const Eigen::Vector3d r = V.transpose() * n;
  int k = 0;
  r.cwiseAbs().minCoeff(&k);
  *residual = r(k);
  return k;
}

// Truncated quadratic support: a segment on a direction counts its length, one at the
// threshold nothing, so between two hypotheses the one the segments fit more tightly wins.
double support(const Eigen::Matrix3d& V, const std::vector<SphereSegment>& segments, double threshold) {
  double score = 0.0;
  for (const SphereSegment& s : segments) {
    const double r = (V.transpose() * s.normal).cwiseAbs().minCoeff() / threshold;
    if (r < 1.0) score += s.length_rad * (1.0 - r * r);
  }
  return score;
}

// Columns v1, v2 and v1 x v2 from unit v1 and a vector v2 not parallel to it.
std::optional<Eigen::Matrix3d> triple(const Eigen::Vector3d& v1, const Eigen::Vector3d& v2_raw, int first_column) {
  const Eigen::Vector3d v2 = v2_raw - v2_raw.dot(v1) * v1;
  if (v2.norm() < kMinCrossNorm) return std::nullopt;
  Eigen::Matrix3d V;
  V.col(first_column) = v1;
  V.col((first_column + 1) % 3) = v2.normalized();
  V.col((first_column + 2) % 3) = v1.cross(v2.normalized());
  return V;
}

// A hypothesis from the fewest segments: without a known up, v1 = n1 x n2 (the direction
// two segments share), v2 on v1's great circle and on n3's, v3 = v1 x v2; with it, v2 on
// the horizon and on one segment's great circle.
std::optional<Eigen::Matrix3d> hypothesis(const std::vector<SphereSegment>& segments,
                                          std::discrete_distribution<std::size_t>& pick, std::mt19937_64& rng,
                                          const std::optional<Eigen::Vector3d>& known_up) {
  if (known_up) {
    const Eigen::Vector3d v2 = known_up->cross(segments[pick(rng)].normal);
    if (v2.norm() < kMinCrossNorm) return std::nullopt;
    return triple(*known_up, v2, 2);
  }
  const Eigen::Vector3d v1 = segments[pick(rng)].normal.cross(segments[pick(rng)].normal);
  if (v1.norm() < kMinCrossNorm) return std::nullopt;
  const Eigen::Vector3d v2 = v1.normalized().cross(segments[pick(rng)].normal);
  if (v2.norm() < kMinCrossNorm) return std::nullopt;
  return triple(v1.normalized(), v2, 0);
}

// The nearest orthonormal matrix (no drift after many small updates).
Eigen::Matrix3d orthonormalised(const Eigen::Matrix3d& V) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(V, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

// Gauss-Newton over V <- exp([w]x) V minimising sum length (n . v_k)^2, each segment on
// its nearest direction if within the threshold; the residual's derivative is
// d(n . v)/dw = v x n. With a known up, w is restricted to the up axis.
Eigen::Matrix3d refine(Eigen::Matrix3d V, const std::vector<SphereSegment>& segments, double threshold,
                       const std::optional<Eigen::Vector3d>& known_up) {
  for (int iteration = 0; iteration < 30; ++iteration) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (const SphereSegment& s : segments) {
      double r = 0.0;
      const int k = nearestDirection(V, s.normal, &r);
      if (std::abs(r) >= threshold) continue;
      const Eigen::Vector3d J = V.col(k).cross(s.normal);
      H += s.length_rad * J * J.transpose();
      g += s.length_rad * r * J;
    }
    Eigen::Vector3d w;
    if (known_up) {
      const double h = known_up->dot(H * *known_up);
      if (!(h > 0.0)) break;
      w = -(known_up->dot(g) / h) * *known_up;
    } else {
      // A little damping: with segments on one direction only, the turn about it is free.
      w = -(H + 1e-9 * H.trace() * Eigen::Matrix3d::Identity()).ldlt().solve(g);
    }
    if (!w.allFinite()) break;
    V = orthonormalised(Eigen::AngleAxisd(w.norm(), w.norm() > 0.0 ? w.normalized() : Eigen::Vector3d::UnitZ()) * V);
    if (known_up) V.col(2) = *known_up;
    if (w.norm() < 1e-10) break;
  }
  return V;
}

}  // namespace

VanishingDirections fitVanishingDirections(const std::vector<SphereSegment>& segments, double inlier_rad,
                                           int ransac_iterations, std::uint64_t seed,
                                           const std::optional<Eigen::Vector3d>& known_up) {
  const double threshold = std::sin(inlier_rad);
  // Longer segments have better-known great circles: sample them more often.
  std::vector<double> lengths;
  for (const SphereSegment& s : segments) lengths.push_back(s.length_rad);
  std::discrete_distribution<std::size_t> pick(lengths.begin(), lengths.end());
  std::mt19937_64 rng(seed);

  // A minimal sample's directions are off by about a segment's noise, so hypotheses are
  // scored, and first refined, with a doubled threshold.
  // The hypotheses are drawn in order from the one generator and scored on all cores;
  // the first of the best wins, so the result does not depend on the thread count.
  std::vector<std::optional<Eigen::Matrix3d>> hypotheses;
  hypotheses.reserve(static_cast<std::size_t>(ransac_iterations));
  for (int i = 0; i < ransac_iterations; ++i) hypotheses.push_back(hypothesis(segments, pick, rng, known_up));
  std::vector<double> supports(hypotheses.size(), -1.0);
  constexpr int kChunk = 64;  // hypotheses per task: each is a pass over every segment
  const int chunks = (ransac_iterations + kChunk - 1) / kChunk;
  forEachRow(chunks, 0, [&](int chunk) {
    const std::size_t end = std::min(hypotheses.size(), static_cast<std::size_t>(chunk + 1) * kChunk);
    for (std::size_t i = static_cast<std::size_t>(chunk) * kChunk; i < end; ++i) {
      if (hypotheses[i]) supports[i] = support(*hypotheses[i], segments, 2.0 * threshold);
    }
  });
  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  double best_support = -1.0;
  for (std::size_t i = 0; i < hypotheses.size(); ++i) {
    if (hypotheses[i] && supports[i] > best_support) best_support = supports[i], best = *hypotheses[i];
  }

  VanishingDirections out;
  out.directions = refine(refine(best, segments, 2.0 * threshold, known_up), segments, threshold, known_up);
  double squares = 0.0, weights = 0.0;
  for (const SphereSegment& s : segments) {
    double r = 0.0;
    const int k = nearestDirection(out.directions, s.normal, &r);
    if (std::abs(r) >= threshold) continue;
    ++out.inliers[static_cast<std::size_t>(k)];
    out.inlier_length_rad[static_cast<std::size_t>(k)] += s.length_rad;
    squares += s.length_rad * r * r;
    weights += s.length_rad;
  }
  out.rms_residual_rad = weights > 0.0 ? std::asin(std::min(1.0, std::sqrt(squares / weights))) : 0.0;
  return out;
}

}  // namespace room_reverb::core::vision_detail
