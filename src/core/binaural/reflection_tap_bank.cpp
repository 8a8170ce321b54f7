#include "room_reverb/binaural/reflection_tap_bank.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/lpc.h"
#include "room_reverb/rsao/reflection_tap.h"

namespace room_reverb::core {
namespace {

// Cubic Lagrange interpolation needs the samples one before and two after the read
// position: a delay under two samples would read ahead of what has arrived.
constexpr double kMinDelaySamples = 2.0;

}  // namespace

ReflectionTapBank::ReflectionTapBank(const std::vector<EarlyReflection>& reflections,
                                     const ReflectionTapBankOptions& options)
    : options_(options) {
  if (options_.order < 0 || options_.order > 3) throw InputError("reflection taps: order must be 0 to 3");
  if (options_.block_size == 0) throw InputError("reflection taps: block_size must be positive");
  if (!(options_.max_delay_s > 0.0) || options_.max_delay_s > 10.0) {
    throw InputError("reflection taps: max_delay_s must be in (0, 10] s");
  }
  if (!(options_.analysis_window_s > 0.0)) throw InputError("reflection taps: analysis_window_s must be positive");
  channels_ = static_cast<std::size_t>(ambisonicChannelCount(options_.order));
  const auto capacity = static_cast<std::size_t>(std::ceil(options_.max_delay_s * kInternalSampleRateHz));
  // Each sample is written twice, at i and i + size, so that the four samples an
  // interpolation reads are always contiguous and need no wrap test per sample.
  history_size_ = capacity + options_.block_size + 8;
  history_.assign(2 * history_size_, 0.0f);
  tap_signal_.assign(options_.block_size, 0.0f);
  ramp_.resize(options_.block_size);
  for (std::size_t n = 0; n < ramp_.size(); ++n) {
    ramp_[n] = static_cast<float>(static_cast<double>(n + 1) / static_cast<double>(options_.block_size));
  }
  taps_.resize(reflections.size());
  for (std::size_t k = 0; k < reflections.size(); ++k) {
    EarlyReflection unit = reflections[k];
    unit.level = 1.0;
    unit.time_of_arrival_s = 0.0;
    const ReflectionTap shaped = shapeReflectionTap(unit, k, options_.analysis_window_s, 0.020, "reflection taps");
    Tap& tap = taps_[k];
    tap.unit_gain = shaped.gain;
    const std::vector<BiquadSection> sections =
        !unit.sos.empty() ? unit.sos
                          : (unit.lpc.size() > 1 ? allPoleToSections(unit.lpc, unit.lpc_gain) : std::vector<BiquadSection>{});
    for (const BiquadSection& s : sections) tap.sections.push_back({s.b0, s.b1, s.b2, s.a1, s.a2});
    tap.gains_from.assign(channels_, 0.0);
    tap.gains_to.assign(channels_, 0.0);
  }
}

void ReflectionTapBank::setTargets(const std::vector<TapTarget>& targets) {
  if (targets.size() != taps_.size()) {
    throw InputError("reflection taps: " + std::to_string(targets.size()) + " targets for " +
                     std::to_string(taps_.size()) + " taps");
  }
  const double max_delay = options_.max_delay_s * kInternalSampleRateHz;
  for (std::size_t k = 0; k < taps_.size(); ++k) {
    const TapTarget& t = targets[k];
    Tap& tap = taps_[k];
    if (!std::isfinite(t.delay_s) || !std::isfinite(t.level) || !t.direction.allFinite() || t.direction.norm() < 1e-9) {
      continue;
    }
    const double amplitude = std::max(t.level, 0.0) * tap.unit_gain;
    // A silent target fades the tap out where it is, without moving it.
    if (amplitude == 0.0) {
      tap.amplitude_to = 0.0;
      continue;
    }
    double delay = t.delay_s * kInternalSampleRateHz;
    if (delay > max_delay) {
      delay = max_delay;
      ++clamped_targets_;
    }
    tap.delay_to = std::max(delay, kMinDelaySamples);
    tap.amplitude_to = amplitude;
    tap.gains_to = sn3dHarmonics(options_.order, t.direction.normalized());
    // A tap that was silent starts where it is now, fading in, not gliding from where it
    // was last heard; its filter starts from rest.
    if (tap.amplitude_from == 0.0) {
      tap.delay_from = tap.delay_to;
      tap.gains_from = tap.gains_to;
      for (Section& s : tap.sections) s.s1 = s.s2 = 0.0;
    }
  }
}

void ReflectionTapBank::fadeOut() {
  for (Tap& tap : taps_) tap.amplitude_to = 0.0;
}

void ReflectionTapBank::process(const float* source, float* const* field) {
  const std::size_t frames = options_.block_size;
  const std::size_t size = history_size_;
  const std::size_t block_start = write_;
  for (std::size_t n = 0; n < frames; ++n) {
    const float v = std::isfinite(source[n]) ? source[n] : 0.0f;
    history_[write_] = v;
    history_[write_ + size] = v;
    write_ = write_ + 1 == size ? 0 : write_ + 1;
  }
  const float* history = history_.data();
  const double inverse_frames = 1.0 / static_cast<double>(frames);
  for (Tap& tap : taps_) {
    if (tap.amplitude_from == 0.0 && tap.amplitude_to == 0.0) continue;
    // The read position n - delay(n) with delay(n) = from + (n + 1) (to - from) / frames
    // advances by a constant per sample. Where it advances by 0 to 2 samples (any listener
    // slower than sound) it is stepped, its whole part kept as an index into the ring,
    // instead of taking a floor per sample; the ring's doubling is chosen once for the block.
    const double delay_step = (tap.delay_to - tap.delay_from) * inverse_frames;
    const double advance = 1.0 - delay_step;
    const double start = -(tap.delay_from + delay_step);
    const double start_whole = std::floor(start);
    long index = static_cast<long>(block_start) + static_cast<long>(size) + static_cast<long>(start_whole);
    const long reach = static_cast<long>(2 * frames) + 4;  // the furthest the index moves, and the read's span
    if (index + reach >= static_cast<long>(2 * size)) index -= static_cast<long>(size);
    const bool stepped = advance >= 0.0 && advance < 2.0 && index >= 1 && index + reach < static_cast<long>(2 * size);
    double t = start - start_whole;
    const double amplitude_change = tap.amplitude_to - tap.amplitude_from;
    for (std::size_t n = 0; n < frames; ++n) {
      if (!stepped) {
        const double u = static_cast<double>(n + 1) * inverse_frames;
        const double position = static_cast<double>(n) - (tap.delay_from + u * (tap.delay_to - tap.delay_from));
        const double whole = std::floor(position);
        t = position - whole;
        index = static_cast<long>(block_start) + static_cast<long>(size) + static_cast<long>(whole);
        if (index + 2 >= static_cast<long>(2 * size)) index -= static_cast<long>(size);
      }
      const float* x = history + index;
      double y = -t * (t - 1.0) * (t - 2.0) / 6.0 * x[-1] + (t + 1.0) * (t - 1.0) * (t - 2.0) / 2.0 * x[0] -
                 (t + 1.0) * t * (t - 2.0) / 2.0 * x[1] + (t + 1.0) * t * (t - 1.0) / 6.0 * x[2];
      for (Section& s : tap.sections) {
        const double out = s.b0 * y + s.s1;
        s.s1 = s.b1 * y - s.a1 * out + s.s2;
        s.s2 = s.b2 * y - s.a2 * out;
        y = out;
      }
      tap_signal_[n] = static_cast<float>(y * (tap.amplitude_from + static_cast<double>(ramp_[n]) * amplitude_change));
      if (stepped) {
        t += advance;
        while (t >= 1.0) {
          t -= 1.0;
          ++index;
        }
      }
    }
    // In single precision, as the field is, with the glide's weights from a table and
    // the buffers declared unaliased: so the loop vectorises (a sample index converted to
    // float in the loop kept it scalar, and it was half the taps' cost).
    const float* __restrict signal = tap_signal_.data();
    const float* __restrict ramp = ramp_.data();
    for (std::size_t c = 0; c < channels_; ++c) {
      const auto from = static_cast<float>(tap.gains_from[c]);
      const auto change = static_cast<float>(tap.gains_to[c] - tap.gains_from[c]);
      float* __restrict out = field[c];
      for (std::size_t n = 0; n < frames; ++n) out[n] += (from + change * ramp[n]) * signal[n];
    }
    tap.delay_from = tap.delay_to;
    tap.amplitude_from = tap.amplitude_to;
    tap.gains_from = tap.gains_to;
  }
}

}  // namespace room_reverb::core
