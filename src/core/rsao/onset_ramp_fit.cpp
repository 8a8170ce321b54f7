#include "room_reverb/rsao/onset_ramp_fit.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/rsao/late_envelope.h"
#include "room_reverb/rsao/rsao_resynthesis.h"

namespace room_reverb::core {
namespace {

constexpr double kFs = kInternalSampleRateHz;
constexpr int kBisectionSteps = 20;  // 80 dB of log range to 1e-4 dB
// Longer than the band filters' ringing: the 63 Hz band's energy over a span read 0.14 % apart
// between resyntheses 0.1 and 0.15 s past its end (OnsetRampFit.AddedReflectionsYieldTheirBandEnergy).
constexpr double kFilterMarginS = 0.2;
// The least rate of the bands' energy envelopes for the early course's energies: a sum
// over a window of 50-150 ms errs by at most half a sample at each edge, 0.125 ms at
// 4 kHz.
constexpr double kEnvelopeRateHz = 4000.0;

double energyBetween(const std::vector<float>& x, std::size_t from, std::size_t to) {
  double sum = 0.0;
  for (std::size_t n = from; n < std::min(to, x.size()); ++n) sum += double(x[n]) * x[n];
  return sum;
}

// The onset level (bisected on its logarithm over max_gain either side of the band's level)
// whose envelope holds `energy` over [from, to); the lowest when even that holds more.
double onsetLevelHolding(LateReverb& late, std::size_t b, std::size_t from, std::size_t to, double energy,
                         double max_gain) {
  LateReverbBand& band = late.bands[b];
  double low = std::log(band.level / max_gain), high = std::log(band.level * max_gain);
  band.onset_level = std::exp(low);
  if (lateEnvelopeEnergy(late, b, from, to, kFs) >= energy) return band.onset_level;
  band.onset_level = std::exp(high);
  if (lateEnvelopeEnergy(late, b, from, to, kFs) <= energy) return band.onset_level;
  for (int step = 0; step < kBisectionSteps; ++step) {
    const double mid = 0.5 * (low + high);
    band.onset_level = std::exp(mid);
    (lateEnvelopeEnergy(late, b, from, to, kFs) < energy ? low : high) = mid;
  }
  return std::exp(0.5 * (low + high));
}

// Per band, the energy of `x` over samples [from, to) at kFs, in those samples' units,
// from each band's energy envelope (BandFilterBank::extractEnergyEnvelope): an envelope
// at rate r holds the band's energy per sample at kFs / r times fewer samples, each
// standing for that many.
std::vector<double> bandEnergiesBetween(const BandFilterBank& bank, const std::vector<float>& x, std::size_t from,
                                        std::size_t to) {
  const BandFilterBank::PaddedSpectrum spectrum = bank.analyse(x);
  std::vector<double> energies;
  for (std::size_t b = 0; b < bank.bands().size(); ++b) {
    const BandFilterBank::BandEnergy band = bank.extractEnergyEnvelope(spectrum, b, kEnvelopeRateHz);
    const double ratio = band.sample_rate_hz / kFs;
    const auto first = static_cast<std::size_t>(std::lround(static_cast<double>(from) * ratio));
    const auto last = std::min(band.energy.size(), static_cast<std::size_t>(std::lround(static_cast<double>(to) * ratio)));
    double sum = 0.0;
    for (std::size_t i = first; i < last; ++i) sum += band.energy[i];
    energies.push_back(sum / ratio);
  }
  return energies;
}

}  // namespace

void fitOnsetRamps(const std::vector<float>& w, Rsao& rsao, const OnsetRampFitOptions& options) {
  LateReverb& late = rsao.late;
  if (late.bands.empty() || rsao.reflections.empty() || !(late.mixing_time_s > late.onset_s)) return;

  const double start_s = std::max(0.0, rsao.reflections.front().time_of_arrival_s - 0.001);
  const auto from = static_cast<std::size_t>(std::floor(start_s * kFs));
  late.course_end_s = late.mixing_time_s + options.course_extension_s;
  const auto to = std::min(w.size(), static_cast<std::size_t>(std::ceil(late.course_end_s * kFs)));
  if (from >= to) return;
  // Only the span and a margin for the band filters' responses are analysed.
  const std::size_t length = std::min(w.size(), to + static_cast<std::size_t>(kFilterMarginS * kFs));

  // The taps alone, as the resynthesis plays them.
  ResynthesisOptions taps_only;
  taps_only.include_late = false;
  taps_only.analysis_window_s = options.analysis_window_s;
  taps_only.duration_s = static_cast<double>(length) / kFs;
  const std::vector<float> taps = resynthesizeRsao(rsao, taps_only).channels[kAcnW];

  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  const BandFilterBank bank(bands, kFs);
  const std::vector<double> measured = bandEnergiesBetween(bank, std::vector<float>(w.begin(), w.begin() + length), from, to);
  const std::vector<double> played = bandEnergiesBetween(bank, taps, from, to);

  const double max_gain = std::pow(10.0, options.max_onset_gain_db / 20.0);
  for (std::size_t b = 0; b < late.bands.size() && b < bands.size(); ++b) {
    LateReverbBand& band = late.bands[b];
    band.onset_level = 0.0;
    const double residual = measured[b] - played[b];
    if (!(band.level > 0.0) || residual <= lateEnvelopeEnergy(late, b, from, to, kFs)) continue;
    band.onset_level = onsetLevelHolding(late, b, from, to, residual, max_gain);
  }
}

double yieldOnsetEnergy(std::vector<EarlyReflection>& added, Rsao& rsao, const OnsetRampFitOptions& options) {
  LateReverb& late = rsao.late;
  if (added.empty() || late.bands.empty() || rsao.reflections.empty() || !(late.mixing_time_s > late.onset_s)) return 1.0;
  const double start_s = std::max(0.0, rsao.reflections.front().time_of_arrival_s - 0.001);
  const auto from = static_cast<std::size_t>(std::floor(start_s * kFs));
  const double end_s = std::max(late.course_end_s, late.mixing_time_s);
  const auto to = static_cast<std::size_t>(std::ceil(end_s * kFs));
  if (from >= to) return 1.0;
  double last_s = 0.0;
  for (const EarlyReflection& r : added) last_s = std::max(last_s, r.time_of_arrival_s);
  const std::size_t length = std::max(to, static_cast<std::size_t>(std::ceil(last_s * kFs))) +
                             static_cast<std::size_t>(kFilterMarginS * kFs);

  // What the added taps bring to each band as the resynthesis plays them beside the RSAO's
  // own: the band energy of all the taps less that of the RSAO's alone (taps close in time
  // add coherently in the low bands, so their energies do not simply add).
  ResynthesisOptions taps_only;
  taps_only.include_late = false;
  taps_only.analysis_window_s = options.analysis_window_s;
  taps_only.duration_s = static_cast<double>(length) / kFs;
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  const BandFilterBank bank(bands, kFs);
  const auto band_energies = [&](const std::vector<EarlyReflection>& extra, double extra_gain) {
    Rsao taps = rsao;
    for (EarlyReflection r : extra) {
      r.level *= extra_gain;
      taps.reflections.push_back(r);
    }
    std::vector<double> energy;
    for (const std::vector<float>& band : bank.split(resynthesizeRsao(taps, taps_only).channels[kAcnW])) {
      energy.push_back(energyBetween(band, from, to));
    }
    return energy;
  };
  // The band energy of the RSAO's taps with the added ones at gain g is, by superposition,
  // own + 2 g cross + g^2 alone: exact for any g from three resyntheses.
  const std::vector<double> own = band_energies({}, 0.0);
  const std::vector<double> with_added = band_energies(added, 1.0);
  Rsao only_added = rsao;
  only_added.reflections = added;
  std::vector<double> alone;
  for (const std::vector<float>& band : bank.split(resynthesizeRsao(only_added, taps_only).channels[kAcnW])) {
    alone.push_back(energyBetween(band, from, to));
  }
  const auto brought = [&](std::size_t b, double g) {
    return g * g * alone[b] + g * (with_added[b] - own[b] - alone[b]);
  };

  // What each band holds now and the least it can hold (its course from max_onset_gain_db
  // under its level); the largest gain at which every well-estimated band can give what
  // the added reflections bring.
  const double max_gain = std::pow(10.0, options.max_onset_gain_db / 20.0);
  const std::size_t count = std::min(late.bands.size(), bands.size());
  std::vector<double> held(count, 0.0);
  double gain = 1.0;
  for (std::size_t b = 0; b < count; ++b) {
    LateReverbBand& band = late.bands[b];
    if (!(band.level > 0.0)) continue;
    held[b] = lateEnvelopeEnergy(late, b, from, to, kFs);
    const double kept = band.onset_level;
    band.onset_level = band.level / max_gain;
    const double available = std::max(held[b] - lateEnvelopeEnergy(late, b, from, to, kFs), 0.0);
    band.onset_level = kept;
    const bool well_estimated = bands[b].nominal_hz >= 125.0 && bands[b].nominal_hz <= 4000.0;
    if (!well_estimated || brought(b, 1.0) <= available || !(alone[b] > 0.0)) continue;
    // g^2 alone + g (2 cross) = available, its root in [0, 1].
    const double half_cross = 0.5 * (with_added[b] - own[b] - alone[b]);
    const double g = (-half_cross + std::sqrt(std::max(half_cross * half_cross + alone[b] * available, 0.0))) / alone[b];
    gain = std::min(gain, std::clamp(g, 0.0, 1.0));
  }
  for (EarlyReflection& r : added) r.level *= gain;
  for (std::size_t b = 0; b < count; ++b) {
    if (!(late.bands[b].level > 0.0)) continue;
    late.bands[b].onset_level = onsetLevelHolding(late, b, from, to, held[b] - brought(b, gain), max_gain);
  }
  return gain;
}

}  // namespace room_reverb::core
