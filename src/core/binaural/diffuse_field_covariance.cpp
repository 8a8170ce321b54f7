#include "diffuse_field_covariance.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace room_reverb::core {
namespace {

// Below this ratio of the smaller to the larger eigenvalue a covariance is treated as
// singular: there is nothing sound to mix from (silent bins, DC of a high-passed set).
constexpr double kSingularRatio = 1e-9;

bool wellConditioned(const Eigen::Matrix2cd& covariance) {
  const double trace = covariance.trace().real();
  const double determinant = covariance.determinant().real();
  return trace > 0.0 && determinant > kSingularRatio * trace * trace;
}

}  // namespace

Eigen::Matrix2cd hrtfDiffuseFieldCovariance(const Eigen::MatrixXcd& hrtfs, const Eigen::VectorXd& weights) {
  return hrtfs.transpose() * weights.asDiagonal() * hrtfs.conjugate();
}

void constrainDiffuseFieldCovariance(Eigen::MatrixXcd& decoder, const Eigen::Matrix2cd& target,
                                     const Eigen::VectorXd& channel_powers) {
  const Eigen::Matrix2cd actual = decoder.transpose() * channel_powers.asDiagonal() * decoder.conjugate();
  if (!wellConditioned(actual) || !wellConditioned(target)) return;
  const Eigen::Matrix2cd l_actual = actual.llt().matrixL();
  const Eigen::Matrix2cd l_target = target.llt().matrixL();
  const Eigen::JacobiSVD<Eigen::Matrix2cd> svd(l_actual.adjoint() * l_target,
                                                Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix2cd rotation = svd.matrixV() * svd.matrixU().adjoint();
  const Eigen::Matrix2cd l_actual_inverse =
      l_actual.triangularView<Eigen::Lower>().solve(Eigen::Matrix2cd::Identity());
  const Eigen::Matrix2cd mix = l_target * rotation * l_actual_inverse;
  decoder = decoder * mix.transpose();
}

}  // namespace room_reverb::core
