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
constexpr double kFilterMarginS = 0.1;  // longer than the 63 Hz band filter's ringing

double energyBetween(const std::vector<float>& x, std::size_t from, std::size_t to) {
  double sum = 0.0;
  for (std::size_t n = from; n < std::min(to, x.size()); ++n) sum += double(x[n]) * x[n];
  return sum;
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
  const std::vector<std::vector<float>> measured = bank.split(std::vector<float>(w.begin(), w.begin() + length));
  const std::vector<std::vector<float>> played = bank.split(taps);

  const double max_gain = std::pow(10.0, options.max_onset_gain_db / 20.0);
  for (std::size_t b = 0; b < late.bands.size() && b < bands.size(); ++b) {
    LateReverbBand& band = late.bands[b];
    band.onset_level = 0.0;
    const double residual = energyBetween(measured[b], from, to) - energyBetween(played[b], from, to);
    if (!(band.level > 0.0) || residual <= lateEnvelopeEnergy(late, b, from, to, kFs)) continue;
    // The energy grows with the onset level: bisect on its logarithm, from far below the
    // mixing-time level (a course rising from almost nothing) to max_onset_gain_db above.
    double low = std::log(band.level / max_gain), high = std::log(band.level * max_gain);
    band.onset_level = std::exp(high);
    if (lateEnvelopeEnergy(late, b, from, to, kFs) <= residual) continue;
    for (int step = 0; step < kBisectionSteps; ++step) {
      const double mid = 0.5 * (low + high);
      band.onset_level = std::exp(mid);
      (lateEnvelopeEnergy(late, b, from, to, kFs) < residual ? low : high) = mid;
    }
    band.onset_level = std::exp(0.5 * (low + high));
  }
}

}  // namespace room_reverb::core
