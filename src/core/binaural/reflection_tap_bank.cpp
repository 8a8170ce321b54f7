#include "room_reverb/binaural/reflection_tap_bank.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/lpc.h"
#include "room_reverb/rsao/reflection_tap.h"
#include "tap_kernels.h"

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
  ramp_.resize(options_.block_size);
  for (std::size_t n = 0; n < ramp_.size(); ++n) {
    ramp_[n] = static_cast<float>(static_cast<double>(n + 1) / static_cast<double>(options_.block_size));
  }
  taps_.resize(reflections.size());
  std::vector<std::vector<BiquadSection>> filters(reflections.size());
  for (std::size_t k = 0; k < reflections.size(); ++k) {
    EarlyReflection unit = reflections[k];
    unit.level = 1.0;
    unit.time_of_arrival_s = 0.0;
    const ReflectionTap shaped = shapeReflectionTap(unit, k, options_.analysis_window_s, 0.020, "reflection taps");
    Tap& tap = taps_[k];
    tap.unit_gain = shaped.gain;
    filters[k] = !unit.sos.empty()
                     ? unit.sos
                     : (unit.lpc.size() > 1 ? allPoleToSections(unit.lpc, unit.lpc_gain) : std::vector<BiquadSection>{});
    sections_ = std::max(sections_, filters[k].size());
    tap.gains_from.assign(channels_, 0.0);
    tap.gains_to.assign(channels_, 0.0);
  }
  lanes_ = (taps_.size() + kTapLanes - 1) / kTapLanes * kTapLanes;
  ++sections_;  // the low-pass, last; b0 = 1 and the rest 0 until a target sets it
  const std::size_t coefficients = sections_ * lanes_;
  b0_.assign(coefficients, 1.0f);
  for (auto* c : {&b1_, &b2_, &a1_, &a2_, &s1_, &s2_}) c->assign(coefficients, 0.0f);
  for (std::size_t k = 0; k < filters.size(); ++k) {
    for (std::size_t s = 0; s < filters[k].size(); ++s) {
      const BiquadSection& f = filters[k][s];
      const std::size_t at = s * lanes_ + k;
      b0_[at] = static_cast<float>(f.b0);
      b1_[at] = static_cast<float>(f.b1);
      b2_[at] = static_cast<float>(f.b2);
      a1_[at] = static_cast<float>(f.a1);
      a2_[at] = static_cast<float>(f.a2);
      // The section runs in single precision (tap_kernels.h): its rounded poles must stay
      // inside the unit circle (the stability triangle |a2| < 1, |a1| < 1 + a2).
      if (!(std::abs(a2_[at]) < 1.0f && std::abs(a1_[at]) < 1.0f + a2_[at])) {
        throw InputError("reflection taps: the filter of reflection " + std::to_string(k) +
                         " has a pole on or outside the unit circle in single precision");
      }
    }
  }
  samples_.assign(options_.block_size * lanes_, 0.0f);
  lane_scratch_.assign(options_.block_size * lanes_, 0.0f);
  tap_signal_.assign(taps_.size() * options_.block_size, 0.0f);
  gains_from_.assign(taps_.size() * channels_, 0.0f);
  gains_change_.assign(taps_.size() * channels_, 0.0f);
}

void ReflectionTapBank::clearFilterState(std::size_t k) {
  for (std::size_t s = 0; s < sections_; ++s) s1_[s * lanes_ + k] = s2_[s * lanes_ + k] = 0.0f;
}

void ReflectionTapBank::setTargets(const std::vector<TapTarget>& targets) {
  if (targets.size() != taps_.size()) {
    throw InputError("reflection taps: " + std::to_string(targets.size()) + " targets for " +
                     std::to_string(taps_.size()) + " taps");
  }
  lowpass_set_ = false;
  const double max_delay = options_.max_delay_s * kInternalSampleRateHz;
  for (std::size_t k = 0; k < taps_.size(); ++k) {
    const TapTarget& t = targets[k];
    Tap& tap = taps_[k];
    if (!std::isfinite(t.delay_s) || !std::isfinite(t.level) || !t.direction.allFinite() || t.direction.norm() < 1e-9 ||
        !(t.lowpass_pole >= 0.0 && t.lowpass_pole < 1.0)) {
      continue;
    }
    const std::size_t lowpass = (sections_ - 1) * lanes_ + k;
    b0_[lowpass] = static_cast<float>(1.0 - t.lowpass_pole);
    a1_[lowpass] = static_cast<float>(-t.lowpass_pole);
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
    sn3dHarmonicsInto(options_.order, t.direction.normalized(), tap.gains_to);
    // A tap that was silent starts where it is now, fading in, not gliding from where it
    // was last heard; its filter starts from rest.
    if (tap.amplitude_from == 0.0) {
      tap.delay_from = tap.delay_to;
      tap.gains_from = tap.gains_to;
      clearFilterState(k);
    }
  }
  for (std::size_t k = 0; k < taps_.size(); ++k) lowpass_set_ = lowpass_set_ || a1_[(sections_ - 1) * lanes_ + k] != 0.0f;
}

void ReflectionTapBank::fadeOut() {
  for (Tap& tap : taps_) tap.amplitude_to = 0.0;
}

void ReflectionTapBank::readTap(std::size_t k, std::size_t block_start) {
  const Tap& tap = taps_[k];
  const std::size_t frames = options_.block_size;
  const auto size = static_cast<long>(history_size_);
  float* out = samples_.data() + k * frames;
  const float* history = history_.data();
  // Sample n is read at n - delay(n), delay(n) = from + (n + 1) step: at block position
  // start + n - n step. Between the moments its whole part changes, the read is
  // x[n + j] at a fraction that moves by -step per sample, a contiguous run that
  // interpolateCubic vectorises; a listener slower than sound (|step| < 1) makes a run of
  // most of the block.
  const double step = (tap.delay_to - tap.delay_from) / static_cast<double>(frames);
  const double start = -(tap.delay_from + step);
  const double last = start - static_cast<double>(frames - 1) * step;
  long base = static_cast<long>(block_start) + size;  // the block's first sample, in the doubled ring
  const long lowest = base + static_cast<long>(std::floor(std::min(start, last))) - 1;
  const long highest = base + static_cast<long>(std::floor(std::max(start, last))) + static_cast<long>(frames) + 2;
  const long shift = highest >= 2 * size ? size : 0;
  if (std::abs(step) < 1.0 && lowest - shift >= 0 && highest - shift < 2 * size) {
    base -= shift;
    std::size_t n = 0;
    while (n < frames) {
      const double q = start - static_cast<double>(n) * step;
      const double whole = std::floor(q);
      // The run lasts while start - m step stays within [whole, whole + 1).
      double end = static_cast<double>(frames);
      if (step > 0.0) end = std::min(end, std::floor((start - whole) / step) + 1.0);
      if (step < 0.0) end = std::min(end, std::ceil((whole + 1.0 - start) / -step));
      const std::size_t run_end = std::max(n + 1, static_cast<std::size_t>(std::max(end, 0.0)));
      interpolateCubic(history + base + static_cast<long>(whole) + static_cast<long>(n), static_cast<float>(q - whole),
                       static_cast<float>(-step), run_end - n, out + n);
      n = run_end;
    }
    return;
  }
  // A jump of more than a sample per sample (a tap set far from where it was): each
  // read placed on its own.
  for (std::size_t n = 0; n < frames; ++n) {
    const double position = start + static_cast<double>(n) * (1.0 - step);
    const double whole = std::floor(position);
    long index = static_cast<long>(block_start) + size + static_cast<long>(whole);
    if (index + 2 >= 2 * size) index -= size;
    interpolateCubic(history + index, static_cast<float>(position - whole), 0.0f, 1, out + n);
  }
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
  bool any = false;
  for (std::size_t k = 0; k < taps_.size(); ++k) {
    const Tap& tap = taps_[k];
    if (tap.amplitude_from == 0.0 && tap.amplitude_to == 0.0) {
      std::fill_n(samples_.data() + k * frames, frames, 0.0f);
      continue;
    }
    readTap(k, block_start);
    any = true;
  }
  if (!any) return;
  // The low-pass section runs while a pole is set and one block after.
  const std::size_t sections = sections_ - ((lowpass_set_ || lowpass_running_) ? 0 : 1);
  lowpass_running_ = lowpass_set_;
  if (sections > 0) {
    runLaneSections({b0_.data(), b1_.data(), b2_.data(), a1_.data(), a2_.data(), s1_.data(), s2_.data(), sections, lanes_},
                    samples_.data(), lane_scratch_.data(), frames);
  }
  // The heard taps' signals scaled by their gliding amplitudes and their encoding glides,
  // packed for encodeGliding.
  const float* ramp = ramp_.data();
  std::size_t heard = 0;
  for (std::size_t k = 0; k < taps_.size(); ++k) {
    Tap& tap = taps_[k];
    if (tap.amplitude_from == 0.0 && tap.amplitude_to == 0.0) continue;
    const auto amplitude_from = static_cast<float>(tap.amplitude_from);
    const auto amplitude_change = static_cast<float>(tap.amplitude_to - tap.amplitude_from);
    const float* __restrict in = samples_.data() + k * frames;
    float* __restrict signal = tap_signal_.data() + heard * frames;
    for (std::size_t n = 0; n < frames; ++n) signal[n] = in[n] * (amplitude_from + ramp[n] * amplitude_change);
    for (std::size_t c = 0; c < channels_; ++c) {
      gains_from_[heard * channels_ + c] = static_cast<float>(tap.gains_from[c]);
      gains_change_[heard * channels_ + c] = static_cast<float>(tap.gains_to[c] - tap.gains_from[c]);
    }
    ++heard;
    tap.delay_from = tap.delay_to;
    tap.amplitude_from = tap.amplitude_to;
    tap.gains_from = tap.gains_to;
  }
  encodeGliding(tap_signal_.data(), heard, gains_from_.data(), gains_change_.data(), channels_, ramp, field, frames);
}

}  // namespace room_reverb::core
