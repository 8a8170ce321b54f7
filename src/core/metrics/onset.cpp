#include "room_reverb/metrics/onset.h"

#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

std::size_t findDirectSoundOnset(const std::vector<float>& rir, double threshold_db) {
  double peak = 0.0;
  for (float sample : rir) peak = std::max(peak, static_cast<double>(sample) * sample);
  if (peak <= 0.0) throw InputError("the impulse response is silent (every sample is zero)");
  const double threshold = peak * std::pow(10.0, -threshold_db / 10.0);
  for (std::size_t n = 0; n < rir.size(); ++n) {
    if (static_cast<double>(rir[n]) * rir[n] >= threshold) return n;
  }
  return 0;  // unreachable: the peak itself passes
}

}  // namespace room_reverb::core
