#include "room_reverb/acoustics/boundary_admittance.h"

#include <algorithm>
#include <cmath>

namespace room_reverb::core {

double randomIncidenceAbsorption(double beta) {
  if (!(beta > 0.0)) return 0.0;
  // Gauss-Legendre would do with fewer points; the composite Simpson rule on 400 panels
  // is exact to 1e-9 here and cheap next to anything that calls it.
  constexpr int kPanels = 400;
  const double half_pi = 0.5 * 3.14159265358979323846;
  const double step = half_pi / kPanels;
  double sum = 0.0;
  for (int k = 0; k <= kPanels; ++k) {
    const double theta = k * step;
    const double c = std::cos(theta);
    const double value = 4.0 * beta * c / ((c + beta) * (c + beta)) * std::sin(2.0 * theta);
    const double weight = (k == 0 || k == kPanels) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
    sum += weight * value;
  }
  return sum * step / 3.0;
}

double admittanceForRandomIncidenceAbsorption(double alpha) {
  if (!(alpha > 0.0)) return 0.0;
  if (alpha >= kMaxRealAdmittanceAbsorption) return kAdmittanceOfMaxAbsorption;
  // Increasing on [0, kAdmittanceOfMaxAbsorption]: bisection.
  double lo = 0.0, hi = kAdmittanceOfMaxAbsorption;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (randomIncidenceAbsorption(mid) < alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace room_reverb::core
