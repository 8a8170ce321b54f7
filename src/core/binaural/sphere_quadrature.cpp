#include "sphere_quadrature.h"

#include <cmath>

namespace room_reverb::core {

Eigen::VectorXd densityCompensatingWeights(const std::vector<Eigen::Vector3d>& directions) {
  constexpr double kPi = 3.14159265358979323846;
  const auto n = static_cast<Eigen::Index>(directions.size());
  Eigen::MatrixXd points(3, n);
  for (Eigen::Index i = 0; i < n; ++i) points.col(i) = directions[static_cast<std::size_t>(i)].normalized();
  // exp(kappa (cos g - 1)) ~ exp(-g^2 / (2 sigma^2)) for small angles g, with kappa = 1 / sigma^2.
  const double sigma = 2.0 * std::sqrt(4.0 * kPi / static_cast<double>(n));
  const double kappa = 1.0 / (sigma * sigma);
  const Eigen::MatrixXd cosines = points.transpose() * points;
  const Eigen::VectorXd density = (kappa * (cosines.array() - 1.0)).exp().rowwise().sum();
  const Eigen::VectorXd weights = density.cwiseInverse();
  return weights / weights.sum();
}

}  // namespace room_reverb::core
