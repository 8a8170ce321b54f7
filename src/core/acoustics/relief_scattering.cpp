#include "room_reverb/acoustics/relief_scattering.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Heights are pooled in bins this wide [m], each at its members' mean height: a wall's
// thousands of cells become at most a few hundred levels, and the double sum runs over
// those. Against the sum over every cell the pooling moves s by under 0.003 up to 4 kHz
// (test_surface_relief).
constexpr double kHeightBin_m = 0.005;

// int_0^1 2 mu cos(a mu) dmu; its series near 0, where the closed form cancels.
double parisCosine(double a) {
  if (std::abs(a) < 1e-3) return 1.0 - a * a / 4.0;
  return 2.0 * (std::sin(a) / a + (std::cos(a) - 1.0) / (a * a));
}

}  // namespace

OctaveBandValues reliefScattering(const std::vector<double>& heights_m, double speed_of_sound_m_s,
                                  const OctaveBandValues& band_centres_hz) {
  if (heights_m.empty()) throw InputError("relief scattering: no heights");
  if (!(speed_of_sound_m_s > 0.0) || !std::isfinite(speed_of_sound_m_s)) {
    throw InputError("relief scattering: the speed of sound must be positive and finite");
  }
  std::map<long, std::pair<double, double>> bins;  // bin -> (sum of heights, count)
  for (double z : heights_m) {
    if (!std::isfinite(z)) throw InputError("relief scattering: a height is not finite");
    auto& bin = bins[std::lround(z / kHeightBin_m)];
    bin.first += z;
    bin.second += 1.0;
  }
  // (mean height, area share) per bin.
  std::vector<std::pair<double, double>> levels;
  levels.reserve(bins.size());
  const double cells = static_cast<double>(heights_m.size());
  for (const auto& [key, bin] : bins) levels.emplace_back(bin.first / bin.second, bin.second / cells);
  OctaveBandValues s{};
  for (int b = 0; b < kOctaveBandCount; ++b) {
    const double two_k = 2.0 * 2.0 * kPi * band_centres_hz[b] / speed_of_sound_m_s;
    double specular = 0.0;
    for (std::size_t j = 0; j < levels.size(); ++j) {
      specular += levels[j].second * levels[j].second;
      for (std::size_t l = j + 1; l < levels.size(); ++l) {
        const double dz = levels[j].first - levels[l].first;
        specular += 2.0 * levels[j].second * levels[l].second * parisCosine(two_k * dz);
      }
    }
    s[b] = std::clamp(1.0 - specular, 0.0, 1.0);
  }
  return s;
}

bool hasRelief(const OctaveBandValues& relief_scattering) {
  return std::any_of(relief_scattering.begin(), relief_scattering.end(), [](double s) { return s > 0.0; });
}

OctaveBandValues combinedScattering(const OctaveBandValues& material_scattering, const OctaveBandValues& relief_scattering) {
  OctaveBandValues s{};
  for (int b = 0; b < kOctaveBandCount; ++b) s[b] = 1.0 - (1.0 - material_scattering[b]) * (1.0 - relief_scattering[b]);
  return s;
}

}  // namespace room_reverb::core
