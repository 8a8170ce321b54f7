#include "room_reverb/rsao/late_envelope.h"

#include <algorithm>
#include <cmath>

namespace room_reverb::core {

bool hasTwoSlopes(const LateReverbBand& b) { return b.second_share > 0.0; }

bool slopesWellFormed(const LateReverbBand& b) {
  if (b.second_share == 0.0) return true;
  return b.second_share > 0.0 && b.second_share < 1.0 && std::isfinite(b.first_decay_constant_per_s) &&
         std::isfinite(b.second_decay_constant_per_s) && b.first_decay_constant_per_s > 0.0 &&
         b.second_decay_constant_per_s > 0.0;
}

double lateDecayGain(const LateReverbBand& b, double since_mixing_s) {
  if (!hasTwoSlopes(b)) return std::exp(-b.decay_constant_per_s * since_mixing_s);
  const double w = b.second_share;
  return std::sqrt((1.0 - w) * std::exp(-2.0 * b.first_decay_constant_per_s * since_mixing_s) +
                   w * std::exp(-2.0 * b.second_decay_constant_per_s * since_mixing_s));
}

double lateDecayLengthS(const LateReverbBand& b, double drop_db) {
  const double log_drop = drop_db * std::log(10.0) / 20.0;  // ln of the amplitude ratio
  if (!hasTwoSlopes(b)) return log_drop / b.decay_constant_per_s;
  // d_b falls monotonically: bisect between the faster slope's time and the slower one's
  // (each alone bounds the sum from below and above).
  const double target = std::exp(-log_drop);
  double low = 0.0, high = log_drop / std::min(b.first_decay_constant_per_s, b.second_decay_constant_per_s);
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (low + high);
    (lateDecayGain(b, mid) > target ? low : high) = mid;
  }
  return high;
}

double lateEnvelopeGain(const LateReverb& late, std::size_t band, double t, OnsetRamp shape) {
  const LateReverbBand& b = late.bands[band];
  if (t < late.onset_s) return 0.0;
  const bool extended = b.onset_level > 0.0 && b.level > 0.0;
  const double join = extended ? std::max(late.mixing_time_s, late.course_end_s) : late.mixing_time_s;
  if (t >= join) return lateDecayGain(b, t - late.mixing_time_s);
  const double u = (t - late.onset_s) / (join - late.onset_s);
  if (!extended) return shape == OnsetRamp::kLinear ? u : 0.5 * (1.0 - std::cos(3.14159265358979323846 * u));
  const double end_gain = lateDecayGain(b, join - late.mixing_time_s);
  return (b.onset_level / b.level) * std::pow(end_gain * b.level / b.onset_level, u);
}

namespace {

// The first sample n >= from with n / fs >= t (as lateEnvelopeGain compares times).
std::size_t firstSampleAtOrAfter(double t, double fs, std::size_t from) {
  if (!(t > 0.0)) return from;
  auto n = static_cast<std::size_t>(std::ceil(t * fs));
  while (n > 0 && static_cast<double>(n - 1) / fs >= t) --n;
  while (static_cast<double>(n) / fs < t) ++n;
  return std::max(n, from);
}

// sum_{k=0}^{count-1} exp(2 (log_first + log_step k)): a geometric series.
double geometricEnergy(double log_first, double log_step, std::size_t count) {
  if (count == 0) return 0.0;
  const double head = std::exp(2.0 * log_first);
  const double x = 2.0 * log_step;
  return x == 0.0 ? head * static_cast<double>(count) : head * std::expm1(x * static_cast<double>(count)) / std::expm1(x);
}

}  // namespace

double lateEnvelopeEnergy(const LateReverb& late, std::size_t band, std::size_t from, std::size_t to, double fs) {
  const LateReverbBand& b = late.bands[band];
  if (to <= from || !(b.level > 0.0)) return 0.0;
  const bool extended = b.onset_level > 0.0;
  const double join = extended ? std::max(late.mixing_time_s, late.course_end_s) : late.mixing_time_s;
  const std::size_t onset_n = std::min(to, firstSampleAtOrAfter(late.onset_s, fs, from));
  const std::size_t join_n = std::min(to, std::max(onset_n, firstSampleAtOrAfter(join, fs, from)));
  double energy = 0.0;
  if (extended && join_n > onset_n) {
    // ln e(n) = ln onset_level + u(n) ln R, u linear in n, R the ratio over the course.
    const double log_ratio = std::log(lateDecayGain(b, join - late.mixing_time_s)) + std::log(b.level / b.onset_level);
    const double span = join - late.onset_s;
    const double u_first = (static_cast<double>(onset_n) / fs - late.onset_s) / span;
    energy += geometricEnergy(std::log(b.onset_level) + u_first * log_ratio, log_ratio / (fs * span), join_n - onset_n);
  } else {
    for (std::size_t n = onset_n; n < join_n; ++n) {
      const double e = b.level * lateEnvelopeGain(late, band, static_cast<double>(n) / fs);
      energy += e * e;
    }
  }
  const double join_since_mixing = static_cast<double>(join_n) / fs - late.mixing_time_s;
  if (!hasTwoSlopes(b)) {
    const double log_first = std::log(b.level) - b.decay_constant_per_s * join_since_mixing;
    return energy + geometricEnergy(log_first, -b.decay_constant_per_s / fs, to - join_n);
  }
  // Each slope's energy term is a geometric series of its own.
  const struct { double share, delta; } slopes[] = {{1.0 - b.second_share, b.first_decay_constant_per_s},
                                                    {b.second_share, b.second_decay_constant_per_s}};
  for (const auto& slope : slopes) {
    if (!(slope.share > 0.0)) continue;
    const double log_first = std::log(b.level) + 0.5 * std::log(slope.share) - slope.delta * join_since_mixing;
    energy += geometricEnergy(log_first, -slope.delta / fs, to - join_n);
  }
  return energy;
}

}  // namespace room_reverb::core
