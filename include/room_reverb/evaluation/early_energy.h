#pragma once
// The early part of a response as a level-versus-time profile per octave band: the energy
// in consecutive short windows after the direct sound, each in dB relative to the direct
// window's energy in the same band. It is where surfaces leave their marks (a reflection's
// level carries the surface's absorption, its time the geometry), which the ISO 3382
// parameters average away. Levels relative to the direct sound make the profile independent
// of the measurement's gain.
#include <cstddef>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {

struct EarlyEnergyOptions {
  std::vector<double> bands_hz{500, 1000, 2000, 4000, 8000};  // octaves with time resolution enough
  double window_s = 0.0025;      // 2.5 ms: about one octave band filter's ring at 500 Hz
  int window_count = 12;         // the direct window and 11 after it: 30 ms, about order 1 to 3
  double lead_s = 0.001;         // the direct window starts this long before the onset
  double floor_db = -30.0;       // windows below this (re the direct window) read as the floor
};

struct EarlyEnergyProfile {
  std::vector<double> bands_hz;
  double window_s = 0.0;
  std::vector<std::vector<double>> level_db;  // [band][window]; window 0 is the direct sound (0 dB)
  bool empty() const { return level_db.empty(); }
};

// The octave bands (standardBands order) whose nominal frequencies are in `nominal_hz` and
// whose upper edges lie below Nyquist: the bands an early profile can analyse.
std::vector<FrequencyBand> analysableOctaves(const std::vector<double>& nominal_hz, double sample_rate_hz);

// `omni`: a 48 kHz (or `sample_rate_hz`) omni response; `onset_sample`: its direct-sound
// onset (ISO 3382-1, as MetricsReport::onset_sample). Bands at or above Nyquist are left out.
EarlyEnergyProfile earlyEnergyProfile(const std::vector<float>& omni, double sample_rate_hz, std::size_t onset_sample,
                                      const EarlyEnergyOptions& options = {});

}  // namespace room_reverb::core
