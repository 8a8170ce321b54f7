#pragma once
// What a diffuse field heard through an HRTF set asks of the two ears' late noises, per
// octave band, and the mix of two independent noises that gives it (private to
// src/core/binaural; the model is described in rsao_binaural.h).
#include <vector>

#include "room_reverb/binaural/diffuse_field.h"

namespace room_reverb::core {

// Per standard octave band (63 Hz .. 16 kHz) of an HRTF set's diffuse-field spectrum
// (diffuse_field.h) at 48 kHz: the interaural coherence (diffuseFieldCoherence) and each
// ear's diffuse-field power response P_ear,b, the power spectrum averaged under the band's
// power-complementary response |H_b|^2 (the band's share of white noise at the ear).
struct DiffuseFieldBands {
  std::vector<double> coherence;
  std::vector<double> power_left;
  std::vector<double> power_right;
};
DiffuseFieldBands diffuseFieldBands(const DiffuseFieldSpectrum& spectrum);

// The ears' stationary band noises from two independent draws n1, n2 (per band, as
// LateNoiseSynthesizer::drawBandNoises gives them, flattened): the symmetric mix
//   left_b = a_b n1_b + s_b n2_b,  right_b = a_b n1_b - s_b n2_b,
//   a_b = sqrt((1 + c_b) / 2),  s_b = sqrt((1 - c_b) / 2),
// whose interaural coherence in band b is a_b^2 - s_b^2 = c_b and whose ears have equal
// power when n1_b and n2_b have (Menzer & Faller's symmetric form: neither ear is n1 alone). Returns {left, right}, each per band.
std::vector<std::vector<std::vector<float>>> mixEarBandNoises(const std::vector<std::vector<float>>& n1,
                                                              const std::vector<std::vector<float>>& n2,
                                                              const std::vector<double>& coherence);

}  // namespace room_reverb::core
