#include "room_reverb/rsao/late_reverb.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/clipping.h"
#include "room_reverb/common/error.h"
#include "room_reverb/metrics/energy_decay.h"
#include "room_reverb/metrics/two_slope_decay.h"

namespace room_reverb::core {
namespace {

const double kLn10 = std::log(10.0);
constexpr double kMinAnalysisS = 0.1;
constexpr double kEnvelopeRateHz = 4000.0;

std::string text(const char* format, double value) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

struct BandMeasurement {
  bool measured = false;       // a plausible decay was fitted
  double delta = 0.0;          // per second
  double remaining_energy = 0.0;  // E_b from the fitted line
  std::string problem;         // first failed reliability check ("" if none)
  TwoSlopeFit bent;            // valid when the decay is bent (twoSlopesFor)
};

// The two-slope fit of a measured band when its decay is bent: the curve falls at least
// min_two_slope_depth_db within reach of the fit (noise_margin_db above the noise), one
// exponential misses it by min_bend_db RMS or more and two miss it by at most
// max_two_slope_error_ratio of that, each slope carrying min_slope_share of the energy.
TwoSlopeFit twoSlopesFor(const EnergyDecay& decay, double range_db, const LateReverbOptions& o) {
  const double depth = std::min(o.two_slope_depth_db, range_db - o.noise_margin_db);
  if (!o.two_slopes || depth < o.min_two_slope_depth_db) return {};
  TwoSlopeFit fit = fitTwoSlopes(decay, -depth);
  const double total = fit.fast_energy + fit.slow_energy;
  const bool bent = fit.valid && fit.one_rms_error_db >= o.min_bend_db &&
                    fit.rms_error_db <= o.max_two_slope_error_ratio * fit.one_rms_error_db &&
                    std::min(fit.fast_energy, fit.slow_energy) >= o.min_slope_share * total;
  if (!bent) fit.valid = false;
  return fit;
}

BandMeasurement measureBand(const std::vector<double>& energy, std::size_t mix, double fs,
                            const LateReverbOptions& o) {
  BandMeasurement m;
  const EnergyDecay decay(energy, mix, fs);
  if (!decay.valid()) {
    m.problem = "noise-dominated: " + decay.lundeby().failure;
    return m;
  }
  const double range = decay.decayRangeDb();
  const double needed = std::abs(o.fit_end_db - o.fit_start_db) + o.noise_margin_db;
  if (range < o.noise_dominated_below_db) {
    m.problem = "noise-dominated: the band rises only " + text("%.1f", range) + " dB above its noise floor";
  } else if (range < needed) {
    m.problem = "too little decay range: " + text("%.1f", range) + " dB above the noise, the " +
                text("%.0f", std::abs(o.fit_end_db - o.fit_start_db)) + " dB fit needs " + text("%.0f", needed);
  }
  const DecayLine line = decay.fitLine(o.fit_start_db, o.fit_end_db);
  if (!line.valid) {
    if (m.problem.empty()) m.problem = "no decay of " + text("%.0f", -o.fit_end_db) + " dB found after the mixing time";
    return m;
  }
  const double t60 = -60.0 / line.slope_db_per_s;
  if (t60 < o.min_plausible_t60_s || t60 > o.max_plausible_t60_s) {
    if (m.problem.empty()) {
      m.problem = "implausible T60 of " + text("%.3g", t60) + " s (plausible " + text("%g", o.min_plausible_t60_s) +
                  "-" + text("%g", o.max_plausible_t60_s) + " s): the band holds little but noise";
    }
    return m;
  }
  m.measured = true;
  m.delta = -line.slope_db_per_s * kLn10 / 20.0;
  m.remaining_energy = decay.energyAfter(0.0) * std::pow(10.0, line.intercept_db / 10.0);
  if (m.problem.empty()) m.bent = twoSlopesFor(decay, range, o);
  return m;
}

// Decay constant for a band without a measured one: linear in log2 frequency between the
// nearest measured bands below and above, the nearest one beyond the ends; `fallback_delta`
// (and `used_fallback` set) when no band was measured.
double substituteDelta(const std::vector<BandMeasurement>& m, const std::vector<FrequencyBand>& bands,
                       std::size_t b, double fallback_delta, bool& used_fallback) {
  int below = -1, above = -1;
  for (int i = static_cast<int>(b) - 1; i >= 0 && below < 0; --i) {
    if (m[static_cast<std::size_t>(i)].measured) below = i;
  }
  for (std::size_t i = b + 1; i < m.size() && above < 0; ++i) {
    if (m[i].measured) above = static_cast<int>(i);
  }
  used_fallback = below < 0 && above < 0;
  if (used_fallback) return fallback_delta;
  if (below < 0) return m[static_cast<std::size_t>(above)].delta;
  if (above < 0) return m[static_cast<std::size_t>(below)].delta;
  const auto lo = static_cast<std::size_t>(below), hi = static_cast<std::size_t>(above);
  const double x = std::log2(bands[b].center_hz), x0 = std::log2(bands[lo].center_hz),
               x1 = std::log2(bands[hi].center_hz);
  return m[lo].delta + (m[hi].delta - m[lo].delta) * (x - x0) / (x1 - x0);
}

// The RMS amplitude over `count` samples from `first` of a signal given by its energy per
// sample.
double rmsOver(const std::vector<double>& energy, std::size_t first, std::size_t count) {
  const std::size_t last = std::min(energy.size(), first + std::max<std::size_t>(1, count));
  double sum = 0.0;
  for (std::size_t n = first; n < last; ++n) sum += energy[n];
  return last > first ? std::sqrt(sum / static_cast<double>(last - first)) : 0.0;
}

void checkOptions(const LateReverbOptions& o) {
  if (!(o.fit_end_db < o.fit_start_db && o.fit_start_db <= 0.0)) {
    throw InputError("late reverb: the fit range needs fit_end_db < fit_start_db <= 0 (the paper: 0 and -20)");
  }
  if (!(o.min_plausible_t60_s > 0.0 && o.max_plausible_t60_s > o.min_plausible_t60_s)) {
    throw InputError("late reverb: the plausible T60 range must be positive and not empty");
  }
  if (!(o.fallback_t60_s > 0.0)) throw InputError("late reverb: fallback_t60_s must be positive");
  if (!(o.substitute_level_window_s > 0.0)) throw InputError("late reverb: substitute_level_window_s must be positive");
  if (o.two_slopes && !(o.min_two_slope_depth_db > 0.0 && o.two_slope_depth_db >= o.min_two_slope_depth_db &&
                        o.min_bend_db >= 0.0 && o.max_two_slope_error_ratio > 0.0 && o.min_slope_share >= 0.0)) {
    throw InputError("late reverb: the two-slope fit needs 0 < min_two_slope_depth_db <= two_slope_depth_db, "
                     "min_bend_db >= 0, max_two_slope_error_ratio > 0 and min_slope_share >= 0");
  }
}

void checkInput(const std::vector<float>& w, double first_reflection_s, double mixing_time_s) {
  if (w.empty()) throw InputError("late reverb: the W channel is empty");
  if (!allSamplesFinite(w)) throw InputError("late reverb: the W channel holds a non-finite sample");
  if (!(first_reflection_s >= 0.0)) throw InputError("late reverb: the first reflection time must be >= 0");
  if (!(mixing_time_s >= first_reflection_s)) {
    throw InputError("late reverb: the mixing time (" + text("%.4f", mixing_time_s) +
                     " s) comes before the first reflection (" + text("%.4f", first_reflection_s) + " s)");
  }
  const double duration = static_cast<double>(w.size()) / kInternalSampleRateHz;
  if (mixing_time_s + kMinAnalysisS > duration) {
    throw InputError("late reverb: the RIR (" + text("%.3f", duration) + " s) ends less than " +
                     text("%.1f", kMinAnalysisS) + " s after the mixing time (" + text("%.3f", mixing_time_s) +
                     " s); pass the whole response, not a truncated one");
  }
}

}  // namespace

LateReverb estimateLateReverb(const std::vector<float>& w, double first_reflection_s, double mixing_time_s,
                              const LateReverbOptions& o) {
  checkOptions(o);
  checkInput(w, first_reflection_s, mixing_time_s);
  const double fs = kInternalSampleRateHz;
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  const BandFilterBank bank(bands, fs);
  // Each band's energy envelope (BandFilterBank::extractEnergyEnvelope): its Schroeder
  // curve and level read the same from it as from the band's samples squared, at a rate
  // set by the band's width (at least kEnvelopeRateHz, a quarter-millisecond grid), so the
  // high octaves cost a fraction of the input's rate.
  const BandFilterBank::PaddedSpectrum spectrum = bank.analyse(w);
  std::vector<BandFilterBank::BandEnergy> split;
  for (std::size_t b = 0; b < bands.size(); ++b) split.push_back(bank.extractEnergyEnvelope(spectrum, b, kEnvelopeRateHz));
  auto samplesAt = [](double seconds, double rate) { return static_cast<std::size_t>(std::lround(seconds * rate)); };

  LateReverb late;
  late.mixing_time_s = mixing_time_s;
  late.onset_s = first_reflection_s;
  late.attack_time_s = mixing_time_s - first_reflection_s;

  const auto first = static_cast<std::size_t>(std::lround(first_reflection_s * fs));
  const std::size_t clipped_at = findClippedRun(w, first, o.clip_run_samples);
  const std::string clipped =
      clipped_at < w.size()
          ? "clipped input: a flat top of full-peak samples at " + text("%.4f", clipped_at / fs) +
                " s, after the first reflection; re-measure with less gain"
          : "";

  std::vector<BandMeasurement> measured;
  for (const BandFilterBank::BandEnergy& band : split) {
    measured.push_back(measureBand(band.energy, samplesAt(mixing_time_s, band.sample_rate_hz), band.sample_rate_hz, o));
  }

  const double fallback_delta = 3.0 * kLn10 / o.fallback_t60_s;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const BandMeasurement& m = measured[b];
    LateReverbBand band;
    band.center_hz = bands[b].center_hz;
    bool used_fallback = false;
    if (m.measured && m.bent.valid) {
      // R(t) = A_1 exp(-a_1 t) + A_2 exp(-a_2 t) is the energy remaining under an envelope
      // whose energy is A_1 a_1 exp(-a_1 t) + A_2 a_2 exp(-a_2 t): level^2 is their sum at the
      // mixing time, each slope's decay constant half its energy rate.
      const double first = m.bent.fast_energy * m.bent.fast_rate_per_s;
      const double second = m.bent.slow_energy * m.bent.slow_rate_per_s;
      band.decay_constant_per_s = m.delta;
      band.level = std::sqrt(first + second);
      band.first_decay_constant_per_s = 0.5 * m.bent.fast_rate_per_s;
      band.second_decay_constant_per_s = 0.5 * m.bent.slow_rate_per_s;
      band.second_share = second / (first + second);
    } else if (m.measured) {
      band.decay_constant_per_s = m.delta;
      band.level = std::sqrt(2.0 * m.delta * m.remaining_energy);
    } else {
      band.decay_constant_per_s = substituteDelta(measured, bands, b, fallback_delta, used_fallback);
      const double rate = split[b].sample_rate_hz;
      band.level = rmsOver(split[b].energy, samplesAt(mixing_time_s, rate), samplesAt(o.substitute_level_window_s, rate));
    }
    band.t60_s = 3.0 * kLn10 / band.decay_constant_per_s;
    std::string reason = !clipped.empty() ? clipped : m.problem;
    if (!m.measured) {
      reason += used_fallback ? "; no band has a measured decay, the fallback T60 of " +
                                    text("%g", o.fallback_t60_s) + " s substituted"
                              : "; decay substituted from the neighbouring bands";
      reason += ", level is the RMS of the " + text("%.0f", 1000.0 * o.substitute_level_window_s) +
                " ms after the mixing time";
    }
    band.reliable = reason.empty();
    band.reason = reason;
    late.bands.push_back(band);
  }
  return late;
}

}  // namespace room_reverb::core
