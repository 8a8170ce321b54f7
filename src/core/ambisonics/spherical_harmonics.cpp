#include "room_reverb/ambisonics/spherical_harmonics.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

double factorial(int n) {
  double f = 1.0;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}

// Associated Legendre function P_l^m(x) without the Condon-Shortley phase.
double legendre(int l, int m, double x) {
  double pmm = 1.0;
  const double somx2 = std::sqrt(std::max(0.0, 1.0 - x * x));
  for (int i = 1; i <= m; ++i) pmm *= (2.0 * i - 1.0) * somx2;
  if (l == m) return pmm;
  double pmmp1 = x * (2.0 * m + 1.0) * pmm;
  if (l == m + 1) return pmmp1;
  double pll = 0.0;
  for (int ll = m + 2; ll <= l; ++ll) {
    pll = ((2.0 * ll - 1.0) * x * pmmp1 - (ll + m - 1.0) * pmm) / (ll - m);
    pmm = pmmp1;
    pmmp1 = pll;
  }
  return pll;
}

}  // namespace

std::vector<double> sn3dHarmonics(int order, const Eigen::Vector3d& direction) {
  std::vector<double> y;
  sn3dHarmonicsInto(order, direction, y);
  return y;
}

void sn3dHarmonicsInto(int order, const Eigen::Vector3d& direction, std::vector<double>& y) {
  if (order < 0 || order > kMaxAmbisonicOrder) throw InputError("ambisonic order must be 0 to 3");
  const Eigen::Vector3d d = direction.normalized();
  const double sin_elevation = std::clamp(d.z(), -1.0, 1.0);
  // cos(m azimuth) and sin(m azimuth) as the powers of (x + iy) / |x + iy|, without a
  // trigonometric call: the renderer's moving taps ask for every tap's harmonics every
  // block. On the vertical axis the azimuth is taken as 0, as atan2(0, 0) gives.
  const double horizontal = std::hypot(d.x(), d.y());
  const double cos_azimuth = horizontal > 0.0 ? d.x() / horizontal : 1.0;
  const double sin_azimuth = horizontal > 0.0 ? d.y() / horizontal : 0.0;
  double cos_m[kMaxAmbisonicOrder + 1] = {1.0}, sin_m[kMaxAmbisonicOrder + 1] = {0.0};
  for (int m = 1; m <= order; ++m) {
    cos_m[m] = cos_m[m - 1] * cos_azimuth - sin_m[m - 1] * sin_azimuth;
    sin_m[m] = sin_m[m - 1] * cos_azimuth + cos_m[m - 1] * sin_azimuth;
  }
  y.resize(static_cast<std::size_t>(ambisonicChannelCount(order)));
  for (int l = 0; l <= order; ++l) {
    for (int m = -l; m <= l; ++m) {
      const int am = std::abs(m);
      const double norm = std::sqrt((m == 0 ? 1.0 : 2.0) * factorial(l - am) / factorial(l + am));
      const double angular = m >= 0 ? cos_m[am] : sin_m[am];
      y[static_cast<std::size_t>(l * l + l + m)] = norm * legendre(l, am, sin_elevation) * angular;
    }
  }
}

}  // namespace room_reverb::core
