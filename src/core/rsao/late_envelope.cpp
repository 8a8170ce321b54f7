#include "room_reverb/rsao/late_envelope.h"

#include <algorithm>
#include <cmath>

namespace room_reverb::core {

double lateEnvelopeGain(const LateReverb& late, std::size_t band, double t, OnsetRamp shape) {
  const LateReverbBand& b = late.bands[band];
  if (t < late.onset_s) return 0.0;
  const bool extended = b.onset_level > 0.0 && b.level > 0.0;
  const double join = extended ? std::max(late.mixing_time_s, late.course_end_s) : late.mixing_time_s;
  if (t >= join) return std::exp(-b.decay_constant_per_s * (t - late.mixing_time_s));
  const double u = (t - late.onset_s) / (join - late.onset_s);
  if (!extended) return shape == OnsetRamp::kLinear ? u : 0.5 * (1.0 - std::cos(3.14159265358979323846 * u));
  const double end_gain = std::exp(-b.decay_constant_per_s * (join - late.mixing_time_s));
  return (b.onset_level / b.level) * std::pow(end_gain * b.level / b.onset_level, u);
}

}  // namespace room_reverb::core
