#include "room_reverb/evaluation/decay_curves.h"

#include <cmath>

#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/metrics/energy_decay.h"

namespace room_reverb::core {

std::vector<double> decayCurveTimes(double step_s, double length_s) {
  std::vector<double> t;
  for (double x = 0.0; x <= length_s + 1e-9; x += step_s) t.push_back(x);
  return t;
}

std::vector<double> bandDecayCurveDb(const std::vector<float>& omni, double sample_rate_hz, std::size_t onset_sample,
                                     double band_hz, double step_s, double length_s) {
  std::vector<FrequencyBand> bands;
  for (const FrequencyBand& b : standardBands(BandResolution::kOctave)) {
    if (b.nominal_hz == band_hz) bands.push_back(b);
  }
  std::vector<double> curve;
  if (bands.empty() || omni.empty()) return curve;
  const BandFilterBank bank(bands, sample_rate_hz);
  const EnergyDecay decay(bank.split(omni).front(), onset_sample, sample_rate_hz);
  const double end = decay.valid() ? static_cast<double>(decay.lundeby().crosspoint) / sample_rate_hz : 0.0;
  for (double t : decayCurveTimes(step_s, length_s)) {
    curve.push_back(decay.valid() && t <= end ? decay.levelDb(t) : std::nan(""));
  }
  return curve;
}

}  // namespace room_reverb::core
