#include "synthetic_rsao.h"

#include <cmath>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::test {

const std::vector<double>& roomLikeT60s() {
  static const std::vector<double> t60 = {1.8, 1.6, 1.4, 1.2, 1.0, 0.9, 0.8, 0.6, 0.45};
  return t60;
}

const std::vector<double>& roomLikeLevels() {
  static const std::vector<double> level = {0.02, 0.03, 0.04, 0.05, 0.05, 0.04, 0.03, 0.02, 0.014};
  return level;
}

core::Rsao roomLikeLateRsao(double duration_s) {
  core::Rsao rsao;
  rsao.duration_s = duration_s;
  const auto bands = core::standardBands(core::BandResolution::kOctave);
  for (std::size_t b = 0; b < bands.size(); ++b) {
    core::LateReverbBand band;
    band.center_hz = bands[b].center_hz;
    band.t60_s = roomLikeT60s()[b];
    band.decay_constant_per_s = 3.0 * std::log(10.0) / band.t60_s;
    band.level = roomLikeLevels()[b];
    rsao.late.bands.push_back(band);
  }
  rsao.late.onset_s = 0.010;
  rsao.late.mixing_time_s = 0.060;
  rsao.late.attack_time_s = 0.050;
  return rsao;
}

}  // namespace room_reverb::test
