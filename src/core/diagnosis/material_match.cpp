#include "room_reverb/diagnosis/material_match.h"

#include <cmath>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {

MaterialMatch nearestMaterial(const OctaveBandValues& absorption, const MaterialLibrary& library) {
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);  // 63 Hz .. 16 kHz
  MaterialMatch best;
  best.max_difference = INFINITY;
  for (const std::string& name : library.names()) {
    const OctaveBandValues& other = library.get(name).absorption;
    MaterialMatch m{name, 0.0, 0.0};
    for (std::size_t b = 0; b < bands.size(); ++b) {
      const double hz = bands[b].nominal_hz;
      if (hz < 125.0 || hz > 8000.0) continue;
      const double d = std::abs(absorption[b] - other[b]);
      if (d > m.max_difference) m = {name, d, hz};
    }
    if (m.max_difference < best.max_difference) best = m;
  }
  if (best.material.empty()) best.max_difference = 0.0;
  return best;
}

}  // namespace room_reverb::core
