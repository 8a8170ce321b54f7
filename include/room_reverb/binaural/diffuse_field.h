#pragma once
// What an HRTF set does to a diffuse field (sound from all directions at once, with
// random phases): the power reaching each ear and the interaural coherence. The late
// reverberation of a binaural rendering should match these, whatever decoder made it.
#include <vector>

#include "room_reverb/binaural/hrtf_set.h"

namespace room_reverb::core {

struct DiffuseFieldSpectrum {
  double bin_spacing_hz = 0.0;  // bin k is at k * bin_spacing_hz, from 0 to Nyquist
  // Re{sum_d w_d L_d conj(R_d)} / sqrt(sum_d w_d |L_d|^2 * sum_d w_d |R_d|^2): 1 where
  // the ears hear the same, near 0 where they are independent, negative in between
  // where they are in antiphase.
  std::vector<double> coherence;
  // sum_d w_d |H_d|^2 per ear: the diffuse-field power response. The weights w_d are the
  // solid angles the directions stand for (densityCompensatingWeights, summing to 1), so
  // a set that crowds some region does not let it dominate; a set that leaves part of
  // the sphere unmeasured stays biased towards the rest.
  std::vector<double> power_left;
  std::vector<double> power_right;
};

// The curves on a grid fine enough to resolve the 63 Hz octave (bins at most 12 Hz
// apart: the HRIRs are zero-padded, which interpolates their spectra).
DiffuseFieldSpectrum diffuseFieldSpectrum(const HrtfSet& hrtfs);

// The same sums over any weighted left/right pairs (HRIRs with their solid angles, or a
// decoder's per-channel filters with each channel's diffuse-field power), zero-padded to
// `fft_size` at `sample_rate_hz`. Pairs longer than fft_size are an InputError.
DiffuseFieldSpectrum weightedPairSpectrum(const std::vector<const Hrir*>& pairs, const std::vector<double>& weights,
                                          std::size_t fft_size, double sample_rate_hz);

// The coherence averaged over the bins of each octave band. A centre that is a standard
// octave band's (nominal 63, 125, ... 16000 Hz or its exact centre, frequency_bands.h)
// takes that band's edges; any other centre c spans c/sqrt(2)..c*sqrt(2). InputError
// for a centre that is not positive, or whose band holds no bin of the spectrum.
std::vector<double> diffuseFieldCoherence(const HrtfSet& hrtfs,
                                          const std::vector<double>& band_centres_hz);
// The same from a spectrum already computed.
std::vector<double> diffuseFieldCoherence(const DiffuseFieldSpectrum& spectrum,
                                          const std::vector<double>& band_centres_hz);

}  // namespace room_reverb::core
