#pragma once
// Lundeby's iterative estimate of where a decay sinks into the background noise
// (Lundeby, Vigran, Bietz, Vorländer, "Uncertainties of measurements in room acoustics",
// Acustica 81, 1995), the truncation point ISO 3382-1 (5.3.3, method b) allows.
#include <cstddef>
#include <string>
#include <vector>

namespace room_reverb::core {

struct LundebyResult {
  bool valid = false;
  std::string failure;           // why no decay was found, when !valid
  std::size_t crosspoint = 0;    // sample (from the start of `energy`) where decay meets noise
  double noise_power = 0.0;      // mean squared sample value of the background noise
  double noise_db = 0.0;         // 10 log10(noise_power)
  double peak_db = 0.0;          // highest 10 ms mean-square level
  double slope_db_per_s = 0.0;   // late decay slope (negative)
  double intercept_db = 0.0;     // level of the late decay line at t = 0
  int iterations = 0;
};

// `energy`: squared impulse response from the direct-sound onset on. `initial_interval_s`:
// the first smoothing interval (Lundeby: 10-50 ms).
LundebyResult lundebyTruncation(const std::vector<double>& energy, double sample_rate_hz,
                                double initial_interval_s = 0.010);

}  // namespace room_reverb::core
