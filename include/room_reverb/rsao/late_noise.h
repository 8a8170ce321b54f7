#pragma once
// The late part of an RSAO as noise (Remaggi et al.; Coleman et al., S3A): per octave band,
// Gaussian band noise under the band's envelope (late_envelope.h), corrected for the
// filter bank's band leakage and matched to its envelope as the estimator will analyse it.
// The model and both corrections are described in rsao_resynthesis.h. This is the piece
// every renderer of the late part shares, in two steps so that a renderer can mix the
// stationary noises of several channels before they are shaped: the ambisonic resynthesis
// shapes four independent draws, the binaural rendering mixes two draws to the ears'
// diffuse-field coherence first (rsao_binaural.h).
#include <cstddef>
#include <memory>
#include <vector>

#include "room_reverb/rsao/rsao.h"
#include "room_reverb/rsao/rsao_resynthesis.h"

namespace room_reverb::core {

class LateNoiseSynthesizer {
 public:
  // Signals of `frames` samples at 48 kHz; uses options.seed, onset_ramp and the match_*
  // fields.
  LateNoiseSynthesizer(std::size_t frames, const ResynthesisOptions& options);
  ~LateNoiseSynthesizer();
  LateNoiseSynthesizer(const LateNoiseSynthesizer&) = delete;
  LateNoiseSynthesizer& operator=(const LateNoiseSynthesizer&) = delete;

  // The next draw from one Gaussian source seeded with options.seed (so the n-th draw of a
  // seed is always the same): per octave band (the nine of 63 Hz .. 16 kHz), stationary
  // Gaussian noise band-limited by the power-complementary band response, of unit mean
  // square. Successive draws are independent.
  std::vector<std::vector<float>> drawBandNoises();

  // Divides each band noise by the root of its short-time mean square, smoothed as the
  // envelope matching smooths it, so that it is one over every span the matching resolves.
  // Draws so flattened have equal power locally, not only on average, so that a mix of them
  // keeps the coherence it asks for under any envelope (a decay weights its first tenth of
  // a second, where two raw draws differ by chance). The resynthesis does not need it.
  void flattenEnvelopes(std::vector<std::vector<float>>& band_noises) const;

  // Per band, the model's mean square over time: level_b^2 e_b(t)^2 (late_envelope.h).
  // `late` must have its nine bands and pass the checks of rsao_render_input.h.
  std::vector<std::vector<double>> targetPowers(const LateReverb& late) const;

  // One channel: the band noises (one draw, or a mix of draws that keeps each band in its
  // band) under amplitudes such that each analysis band follows `target`: the leakage
  // correction, then match_passes passes of envelope matching.
  std::vector<float> shape(const std::vector<std::vector<double>>& target,
                           const std::vector<std::vector<float>>& band_noises);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace room_reverb::core
