#include "room_reverb/evaluation/material_match.h"

#include <cmath>

namespace room_reverb::core {

MaterialMatch nearestMaterial(const OctaveBandValues& absorption, const MaterialLibrary& library) {
  MaterialMatch best;
  best.max_difference = INFINITY;
  for (const std::string& name : library.names()) {
    const OctaveBandValues& other = library.get(name).absorption;
    MaterialMatch m{name, 0.0, 0.0};
    // Bands 1-7 of the nine (63 Hz .. 16 kHz): 125 Hz - 8 kHz.
    for (std::size_t b = 1; b + 1 < static_cast<std::size_t>(kOctaveBandCount); ++b) {
      const double hz = 125.0 * std::ldexp(1.0, static_cast<int>(b) - 1);
      const double d = std::abs(absorption[b] - other[b]);
      if (d > m.max_difference) m = {name, d, hz};
    }
    if (m.max_difference < best.max_difference) best = m;
  }
  if (best.material.empty()) best.max_difference = 0.0;
  return best;
}

}  // namespace room_reverb::core
