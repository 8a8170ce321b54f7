#include "value_noise.h"

#include <algorithm>
#include <cmath>

namespace room_reverb::core::capture_detail {

namespace {

double quinticFade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// Weight of an octave with lattice spacing `cell_m` for a sample footprint: 1 when a
// cell spans two footprints or more, 0 at one footprint or less.
double octaveWeight(double cell_m, double footprint_m) {
  if (footprint_m <= 0.0) return 1.0;
  return std::clamp(cell_m / footprint_m - 1.0, 0.0, 1.0);
}

}  // namespace

double valueNoise(std::uint64_t salt, double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const double tx = quinticFade(x - fx), ty = quinticFade(y - fy);
  const double v00 = latticeUnit(salt, ix, iy), v10 = latticeUnit(salt, ix + 1, iy);
  const double v01 = latticeUnit(salt, ix, iy + 1), v11 = latticeUnit(salt, ix + 1, iy + 1);
  const double a = v00 + (v10 - v00) * tx, b = v01 + (v11 - v01) * tx;
  return a + (b - a) * ty;
}

double stretchedNoise(std::uint64_t salt, double x, double y, double cell_x_m, double cell_y_m, int octaves,
                      double gain, double footprint_m) {
  double sum = 0.0, weight = 1.0, norm = 0.0;
  for (int k = 0; k < octaves; ++k) {
    // The smaller cell size decides whether an octave is resolved.
    const double w = weight * octaveWeight(std::min(cell_x_m, cell_y_m), footprint_m);
    if (w > 0.0) sum += w * (2.0 * valueNoise(hashCombine(salt, static_cast<std::uint64_t>(k)), x / cell_x_m, y / cell_y_m) - 1.0);
    norm += weight;
    weight *= gain;
    cell_x_m *= 0.5;
    cell_y_m *= 0.5;
  }
  return norm > 0.0 ? sum / norm : 0.0;
}

double fractalNoise(std::uint64_t salt, double x, double y, double base_cell_m, int octaves, double gain,
                    double footprint_m) {
  return stretchedNoise(salt, x, y, base_cell_m, base_cell_m, octaves, gain, footprint_m);
}

double lineCoverage(double distance_m, double half_width_m, double footprint_m) {
  const double ramp = std::max(footprint_m, 1e-6);
  return std::clamp((half_width_m - std::abs(distance_m)) / ramp + 0.5, 0.0, 1.0);
}

Cell cellOf(double x, double period) {
  const double q = x / period;
  const double f = std::floor(q);
  return {static_cast<std::int64_t>(f), q - f};
}

}  // namespace room_reverb::core::capture_detail
