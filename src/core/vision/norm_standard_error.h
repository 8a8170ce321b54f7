#pragma once
// The standard error of a fitted vector's length, shared by the estimates that report how
// far a small vector (a turn, an offset's cos and sin parts) is from zero.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace room_reverb::core::vision_detail {

// Of |v| along v's own direction, from v's covariance; where v is zero, the largest of its
// components' standard errors.
template <int N>
double normStandardError(const Eigen::Matrix<double, N, 1>& v, const Eigen::Matrix<double, N, N>& covariance) {
  const double n = v.norm();
  if (!(n > 0.0)) return std::sqrt(std::max(0.0, covariance.diagonal().maxCoeff()));
  const Eigen::Matrix<double, N, 1> u = v / n;
  return std::sqrt(std::max(0.0, u.dot(covariance * u)));
}

}  // namespace room_reverb::core::vision_detail
