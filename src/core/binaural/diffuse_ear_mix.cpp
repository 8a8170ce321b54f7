#include "diffuse_ear_mix.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/binaural/diffuse_field.h"

namespace room_reverb::core {
namespace {

// The power response averaged over band b under |H_b|^2.
double bandPower(const std::vector<double>& power, double bin_spacing_hz, const BandFilterBank& bank, std::size_t b) {
  double weighted = 0.0, weight = 0.0;
  for (std::size_t k = 1; k < power.size(); ++k) {
    const double g = bank.gain(b, static_cast<double>(k) * bin_spacing_hz);
    weighted += g * g * power[k];
    weight += g * g;
  }
  return weight > 0.0 ? weighted / weight : 0.0;
}

}  // namespace

DiffuseFieldBands diffuseFieldBands(const DiffuseFieldSpectrum& spectrum) {
  const std::vector<FrequencyBand> octaves = standardBands(BandResolution::kOctave);
  // The set is at the internal rate (rsao_binaural.cpp checks it); the bank's rate only
  // says which bands lie below Nyquist, all of the nine do.
  const BandFilterBank bank(octaves, kInternalSampleRateHz);
  std::vector<double> centres;
  for (const FrequencyBand& band : octaves) centres.push_back(band.nominal_hz);
  DiffuseFieldBands out;
  out.coherence = diffuseFieldCoherence(spectrum, centres);
  for (std::size_t b = 0; b < octaves.size(); ++b) {
    out.power_left.push_back(bandPower(spectrum.power_left, spectrum.bin_spacing_hz, bank, b));
    out.power_right.push_back(bandPower(spectrum.power_right, spectrum.bin_spacing_hz, bank, b));
  }
  return out;
}

std::vector<std::vector<std::vector<float>>> mixEarBandNoises(const std::vector<std::vector<float>>& n1,
                                                              const std::vector<std::vector<float>>& n2,
                                                              const std::vector<double>& coherence) {
  std::vector<std::vector<std::vector<float>>> ears(2, std::vector<std::vector<float>>(n1.size()));
  for (std::size_t b = 0; b < n1.size(); ++b) {
    const double c = std::clamp(coherence[b], -1.0, 1.0);
    const auto common = static_cast<float>(std::sqrt(0.5 * (1.0 + c)));
    const auto apart = static_cast<float>(std::sqrt(0.5 * (1.0 - c)));
    ears[0][b].resize(n1[b].size());
    ears[1][b].resize(n1[b].size());
    for (std::size_t n = 0; n < n1[b].size(); ++n) {
      ears[0][b][n] = common * n1[b][n] + apart * n2[b][n];
      ears[1][b][n] = common * n1[b][n] - apart * n2[b][n];
    }
  }
  return ears;
}

}  // namespace room_reverb::core
