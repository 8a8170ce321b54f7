#pragma once
// How closely a binaural decoder renders sound compared with rendering it through the HRTF
// set directly: for plane waves, the interaural cues of the decoded response against those
// of the measured HRIR over many directions; for a diffuse field (late reverberation), the
// power reaching each ear and the interaural coherence (diffuse_field.h). The numbers of
// docs/binaural_decoders.md and of the decoder tests.
#include <cstddef>
#include <vector>

#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/diffuse_field.h"
#include "room_reverb/binaural/hrtf_set.h"

namespace room_reverb::core {

struct DecoderComparison {
  std::vector<double> band_centres_hz;  // the octave bands 500 Hz .. 8 kHz (nominal centres)
  std::vector<double> ild_error_db;     // per band: mean over directions of |ILD_decoded - ILD_direct|
  double ild_error_db_mean = 0.0;       // the mean of ild_error_db over the bands
  double itd_error_us = 0.0;            // mean over directions of |ITD_decoded - ITD_direct|, below 1.5 kHz
  double itd_error_us_max = 0.0;        // and its largest value
  std::size_t direction_count = 0;      // directions compared
  // Diffuse field, per band: mean over the ears of |10 log10(P_decoded / P_direct)| (the
  // band-averaged powers), and |coherence_decoded - coherence_direct|.
  std::vector<double> diffuse_level_error_db;
  std::vector<double> diffuse_coherence_error;
  double diffuse_level_error_db_mean = 0.0;   // the means over the bands
  double diffuse_coherence_error_mean = 0.0;
};

// What the decoder does to an SN3D diffuse field (uncorrelated channels of powers
// 1/(2l+1), the field's W at unit power), on the bin grid of `like`, so that the two can be
// compared bin by bin with an HRTF set's diffuseFieldSpectrum().
DiffuseFieldSpectrum decoderDiffuseFieldSpectrum(const BinauralDecoder& decoder, const DiffuseFieldSpectrum& like);

// Compares at the measured directions nearest to `direction_count` near-uniform
// (Fibonacci) directions, so no HRIR interpolation enters the reference. InputError unless
// 21 <= direction_count <= 10000 and the decoder has the HRTF set's sample rate.
DecoderComparison compareDecoderToHrtf(const BinauralDecoder& decoder, const HrtfSet& hrtf,
                                       std::size_t direction_count = 200);

}  // namespace room_reverb::core
