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

constexpr int kOrders = kMaxAmbisonicOrder + 1;

// SN3D normalisation sqrt((2 - delta_m) (l - |m|)! / (l + |m|)!), at [l][|m|]: computed
// once, since the renderer's moving taps ask for every tap's harmonics every block.
struct Sn3dNorms {
  double value[kOrders][kOrders] = {};
  Sn3dNorms() {
    for (int l = 0; l < kOrders; ++l) {
      for (int m = 0; m <= l; ++m) value[l][m] = std::sqrt((m == 0 ? 1.0 : 2.0) * factorial(l - m) / factorial(l + m));
    }
  }
};

// Associated Legendre functions P_l^m(x), m <= l <= order, without the Condon-Shortley
// phase, at [l][m]: the sectoral P_m^m = (2m - 1)!! (1 - x^2)^(m/2), then upwards in l by
// (l - m) P_l^m = (2l - 1) x P_(l-1)^m - (l + m - 1) P_(l-2)^m.
void legendreTable(int order, double x, double p[kOrders][kOrders]) {
  const double somx2 = std::sqrt(std::max(0.0, 1.0 - x * x));
  double pmm = 1.0;
  for (int m = 0; m <= order; ++m) {
    if (m > 0) pmm *= (2.0 * m - 1.0) * somx2;
    p[m][m] = pmm;
    if (m + 1 <= order) p[m + 1][m] = x * (2.0 * m + 1.0) * pmm;
    for (int l = m + 2; l <= order; ++l) {
      p[l][m] = ((2.0 * l - 1.0) * x * p[l - 1][m] - (l + m - 1.0) * p[l - 2][m]) / (l - m);
    }
  }
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
  static const Sn3dNorms norms;
  double legendre[kOrders][kOrders];
  legendreTable(order, sin_elevation, legendre);
  y.resize(static_cast<std::size_t>(ambisonicChannelCount(order)));
  for (int l = 0; l <= order; ++l) {
    for (int m = -l; m <= l; ++m) {
      const int am = std::abs(m);
      const double angular = m >= 0 ? cos_m[am] : sin_m[am];
      y[static_cast<std::size_t>(l * l + l + m)] = norms.value[l][am] * legendre[l][am] * angular;
    }
  }
}

}  // namespace room_reverb::core
