#include "room_reverb/acoustics/launch_density.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

int launchCellOf(const Eigen::Vector3d& direction) {
  const double z = std::clamp(direction.z(), -1.0, 1.0);
  const int zone = std::min(kLaunchZones - 1, static_cast<int>((1.0 - z) * 0.5 * kLaunchZones));
  double phi = std::atan2(direction.y(), direction.x());
  if (phi < 0.0) phi += 2.0 * kPi;
  const int sector = std::min(kLaunchSectors - 1, static_cast<int>(phi / (2.0 * kPi) * kLaunchSectors));
  return zone * kLaunchSectors + sector;
}

LaunchDensity::LaunchDensity() {
  probability_.fill(1.0 / kLaunchCells);
  buildZones();
}

LaunchDensity::LaunchDensity(const std::array<double, kLaunchCells>& cell_weights) {
  double total = 0.0;
  for (double w : cell_weights) {
    if (!(w > 0.0) || !std::isfinite(w)) throw InputError("a launch density needs a positive, finite weight in every cell");
    total += w;
  }
  for (std::size_t c = 0; c < cell_weights.size(); ++c) probability_[c] = cell_weights[c] / total;
  buildZones();
}

LaunchDensity LaunchDensity::fromProbabilities(const std::array<double, kLaunchCells>& probabilities) {
  LaunchDensity density(probabilities);  // checks each cell
  double total = 0.0;
  for (double p : probabilities) total += p;
  if (!(std::abs(total - 1.0) <= 1e-9)) throw InputError("a launch density's probabilities must sum to 1");
  density.probability_ = probabilities;
  density.buildZones();
  return density;
}

void LaunchDensity::buildZones() {
  zone_cdf_[0] = 0.0;
  for (int k = 0; k < kLaunchZones; ++k) {
    double zone = 0.0;
    for (int s = 0; s < kLaunchSectors; ++s) zone += probability_[static_cast<std::size_t>(k * kLaunchSectors + s)];
    zone_cdf_[static_cast<std::size_t>(k) + 1] = zone_cdf_[static_cast<std::size_t>(k)] + zone;
  }
}

LaunchDensity::Draw LaunchDensity::draw(double u, double v) const {
  // The zone holding u (its cumulative probability), and where in it u falls.
  const double total = zone_cdf_[kLaunchZones];
  const double at = std::clamp(u, 0.0, 1.0) * total;
  int zone = static_cast<int>(std::upper_bound(zone_cdf_.begin() + 1, zone_cdf_.end() - 1, at) - (zone_cdf_.begin() + 1));
  const double zone_p = zone_cdf_[static_cast<std::size_t>(zone) + 1] - zone_cdf_[static_cast<std::size_t>(zone)];
  const double t = std::clamp((at - zone_cdf_[static_cast<std::size_t>(zone)]) / zone_p, 0.0, 1.0 - 1e-12);
  // The sector holding v among the zone's sectors, by their share of the zone.
  const std::size_t first = static_cast<std::size_t>(zone) * kLaunchSectors;
  double along = std::clamp(v, 0.0, 1.0 - 1e-12) * zone_p;
  int sector = 0;
  for (; sector < kLaunchSectors - 1 && along >= probability_[first + static_cast<std::size_t>(sector)]; ++sector) {
    along -= probability_[first + static_cast<std::size_t>(sector)];
  }
  const double cell_p = probability_[first + static_cast<std::size_t>(sector)];
  const double s = std::clamp(along / cell_p, 0.0, 1.0 - 1e-12);
  const double z = 1.0 - 2.0 * (static_cast<double>(zone) + t) / kLaunchZones;
  const double phi = 2.0 * kPi * (static_cast<double>(sector) + s) / kLaunchSectors;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  Draw out;
  out.direction = Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
  out.weight = 1.0 / (kLaunchCells * cell_p);
  return out;
}

LaunchDensity lateEnergyDensity(const std::array<double, kLaunchCells>& late_share, double mixture) {
  if (!(mixture >= 0.0 && mixture < 1.0)) throw InputError("a launch density's mixture must be in [0, 1)");
  double total = 0.0;
  for (double s : late_share) {
    if (!(s >= 0.0) || !std::isfinite(s)) throw InputError("the late energy's shares per launch cell must be non-negative");
    total += s;
  }
  if (!(std::abs(total - 1.0) <= 1e-6)) throw InputError("the late energy's shares per launch cell must sum to 1");
  std::array<double, kLaunchCells> weights{};
  for (std::size_t c = 0; c < weights.size(); ++c) weights[c] = (1.0 - mixture) / kLaunchCells + mixture * late_share[c];
  return LaunchDensity(weights);
}

}  // namespace room_reverb::core
