#include "room_reverb/ambisonics/max_re_weights.h"

#include <cmath>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Legendre polynomials P_0..P_n at x by Bonnet's recurrence.
std::vector<double> legendrePolynomials(int n, double x) {
  std::vector<double> p(static_cast<std::size_t>(n) + 1, 1.0);
  if (n >= 1) p[1] = x;
  for (int l = 2; l <= n; ++l) {
    p[static_cast<std::size_t>(l)] = ((2.0 * l - 1.0) * x * p[static_cast<std::size_t>(l) - 1] -
                                      (l - 1.0) * p[static_cast<std::size_t>(l) - 2]) / l;
  }
  return p;
}

}  // namespace

std::vector<double> maxReDegreeWeights(int order) {
  if (order < 0 || order > kMaxAmbisonicOrder) throw InputError("ambisonic order must be 0 to 3");
  const double theta_e = (137.9 * kPi / 180.0) / (order + 1.51);
  return legendrePolynomials(order, std::cos(theta_e));
}

std::vector<double> maxReChannelWeights(int order) {
  const std::vector<double> degree = maxReDegreeWeights(order);
  std::vector<double> channel;
  channel.reserve(static_cast<std::size_t>(ambisonicChannelCount(order)));
  for (int l = 0; l <= order; ++l) channel.insert(channel.end(), 2 * l + 1, degree[static_cast<std::size_t>(l)]);
  return channel;
}

}  // namespace room_reverb::core
