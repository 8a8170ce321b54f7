#include "room_reverb/rsao/direction_of_arrival.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

void requireFirstOrder(const AudioBuffer& ambix) {
  if (ambix.channelCount() < 4) {
    std::ostringstream os;
    os << "direction of arrival needs first-order B-format (4 channels, AmbiX W, Y, Z, X), got "
       << ambix.channelCount() << " channel(s)";
    throw InputError(os.str());
  }
}

// Room-axis velocity components (X, Y, Z) of sample n; AmbiX stores them as ACN 3, 1, 2.
Eigen::Vector3d velocityAt(const AudioBuffer& ambix, std::size_t n) {
  return {ambix.channels[kAcnX][n], ambix.channels[kAcnY][n], ambix.channels[kAcnZ][n]};
}

}  // namespace

double CardioidSteeringStatistics::steeredEnergy(const Eigen::Vector3d& v) const {
  return 0.25 * (energy_w + 2.0 * v.dot(w_cross) + v.dot(covariance * v));
}

double CardioidSteeringStatistics::directness() const {
  const double total = energy_w + covariance.trace();
  // |p| <= sqrt(Eww tr R) <= (Eww + tr R) / 2 (Cauchy-Schwarz, then the means): at most 1.
  return total > 0.0 ? std::min(1.0, 2.0 * w_cross.norm() / total) : 0.0;
}

CardioidSteeringStatistics steeringStatistics(const AudioBuffer& ambix, const SampleWindow& window) {
  requireFirstOrder(ambix);
  CardioidSteeringStatistics stats;
  for (std::size_t i = 0; i < window.weights.size(); ++i) {
    const std::size_t n = window.first + i;
    const double g = window.weights[i];
    const double w = g * ambix.channels[kAcnW][n];
    const Eigen::Vector3d u = g * velocityAt(ambix, n);
    stats.energy_w += w * w;
    stats.w_cross += w * u;
    stats.covariance += u * u.transpose();
  }
  return stats;
}

double steeredCardioidEnergy(const AudioBuffer& ambix, const SampleWindow& window, const Eigen::Vector3d& v) {
  requireFirstOrder(ambix);
  double energy = 0.0;
  for (std::size_t i = 0; i < window.weights.size(); ++i) {
    const std::size_t n = window.first + i;
    const double s = 0.5 * window.weights[i] * (ambix.channels[kAcnW][n] + v.dot(velocityAt(ambix, n)));
    energy += s * s;
  }
  return energy;
}

DirectionOfArrival directionFromVector(const Eigen::Vector3d& v) {
  DirectionOfArrival d;
  const double norm = v.norm();
  d.direction = norm > 0.0 ? Eigen::Vector3d(v / norm) : Eigen::Vector3d::UnitX();
  d.azimuth_rad = std::atan2(d.direction.y(), d.direction.x());
  if (d.azimuth_rad >= kPi) d.azimuth_rad -= 2.0 * kPi;  // atan2 gives (-pi, pi]; DESIGN.md wants [-pi, pi)
  d.elevation_rad = std::asin(std::clamp(d.direction.z(), -1.0, 1.0));
  return d;
}

std::vector<Eigen::Vector3d> sphereGrid(double step_rad) {
  if (!(step_rad > 0.0) || step_rad > 0.25 * kPi) {
    throw InputError("direction grid step must be in (0, 45] degrees (given in radians)");
  }
  const auto count = static_cast<std::size_t>(std::ceil(4.0 * kPi / (step_rad * step_rad)));
  const double golden_angle = kPi * (3.0 - std::sqrt(5.0));
  std::vector<Eigen::Vector3d> grid(count);
  for (std::size_t i = 0; i < count; ++i) {
    // Equal-area rings in z, the azimuth turned by the golden angle each time.
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(count);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden_angle * static_cast<double>(i);
    grid[i] = Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
  }
  return grid;
}

DirectionOfArrival directionByGridSearch(const CardioidSteeringStatistics& stats, double grid_step_rad) {
  const auto grid = sphereGrid(grid_step_rad);
  std::size_t best = 0;
  double best_energy = -1.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double e = stats.steeredEnergy(grid[i]);
    if (e > best_energy) {
      best_energy = e;
      best = i;
    }
  }
  DirectionOfArrival d = directionFromVector(grid[best]);
  d.steered_energy = best_energy;
  return d;
}

DirectionOfArrival directionClosedForm(const CardioidSteeringStatistics& stats) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(stats.covariance);
  const Eigen::Vector3d mu = eig.eigenvalues();  // ascending
  const Eigen::Matrix3d q = eig.eigenvectors();
  const Eigen::Vector3d c = q.transpose() * stats.w_cross;
  const double p_norm = stats.w_cross.norm();

  Eigen::Vector3d v;
  if (p_norm == 0.0) {
    v = q.col(2);  // E = 1/4 [Eww + v^T R v]: the top eigenvector
  } else {
    // ||v(lambda)||^2 = sum c_i^2 / (lambda - mu_i)^2, decreasing above mu_max.
    auto squared_norm = [&](double lambda) {
      double s = 0.0;
      for (int i = 0; i < 3; ++i) {
        if (c(i) != 0.0) s += c(i) * c(i) / ((lambda - mu(i)) * (lambda - mu(i)));
      }
      return s;
    };
    // The top eigenspace (eigenvalues tied with mu_max to rounding) and p's part in it.
    const double scale = std::abs(mu(2)) + p_norm;
    double top_part = 0.0;
    Eigen::Vector3d rest = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) {
      if (mu(2) - mu(i) <= 1e-12 * scale) {
        top_part += c(i) * c(i);
      } else {
        rest += c(i) / (mu(2) - mu(i)) * q.col(i);
      }
    }
    const double rest_squared_norm = rest.squaredNorm();
    double lo = mu(2) + std::abs(c(2));
    double hi = mu(2) + p_norm;
    if (std::sqrt(top_part) <= 1e-10 * p_norm && rest_squared_norm < 1.0) {
      // Hard case: p has (next to) no part along the top eigenspace and the other parts
      // leave length to spare, so lambda = mu_max and the rest of the unit length goes
      // along q_max (on the side of p's part there, if any). Newton could not get there:
      // the root would sit closer to mu_max than rounding can tell.
      v = rest + std::copysign(std::sqrt(1.0 - rest_squared_norm), c(2)) * q.col(2);
    } else {
      // Newton on psi(lambda) = 1/||v|| - 1, nearly linear in lambda (exactly so when one
      // term dominates), kept inside the bracket by bisection.
      double lambda = hi;
      for (int iteration = 0; iteration < 100; ++iteration) {
        const double s = squared_norm(lambda);
        const double psi = 1.0 / std::sqrt(s) - 1.0;
        if (psi > 0.0) hi = lambda; else lo = lambda;
        if (std::abs(psi) < 1e-15 || hi - lo <= 1e-15 * std::abs(hi)) break;
        double slope_sum = 0.0;
        for (int i = 0; i < 3; ++i) {
          if (c(i) != 0.0) slope_sum += c(i) * c(i) / std::pow(lambda - mu(i), 3);
        }
        const double dpsi = slope_sum / (s * std::sqrt(s));
        double next = dpsi > 0.0 ? lambda - psi / dpsi : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        lambda = next;
      }
      v.setZero();
      for (int i = 0; i < 3; ++i) {
        if (c(i) != 0.0) v += c(i) / (lambda - mu(i)) * q.col(i);
      }
    }
  }
  DirectionOfArrival d = directionFromVector(v);
  d.steered_energy = stats.steeredEnergy(d.direction);
  return d;
}

}  // namespace room_reverb::core
