#include "room_reverb/rsao/rsao.h"

#include <cmath>

namespace room_reverb::core {

std::array<double, 3> imageSourcePosition(const EarlyReflection& r) {
  const double horizontal = r.distance_m * std::cos(r.elevation_rad);
  return {horizontal * std::cos(r.azimuth_rad), horizontal * std::sin(r.azimuth_rad),
          r.distance_m * std::sin(r.elevation_rad)};
}

}  // namespace room_reverb::core
