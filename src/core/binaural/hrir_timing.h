#pragma once
// Sub-sample timing of short impulse responses (HRIRs): where the direct sound starts, and
// fractional delays. Private to the binaural sources (hrtf_set.cpp).
#include <complex>
#include <cstddef>
#include <vector>

#include "room_reverb/audio/fft.h"

namespace room_reverb::core::hrir_timing {

// Onset in samples, sub-sample accurate: the first time the band-limited waveform (the
// samples interpolated 8x through the spectrum) reaches `threshold_db` below its peak
// magnitude, refined linearly between the interpolated points. A leading-edge threshold
// rather than a cross-correlation: it needs no reference and gives the interaural delay
// of a single pair, as the usual ITD threshold estimators do. 0 for a silent response.
double onsetSamples(const std::vector<float>& response, double threshold_db = 20.0);

// Sums weighted, fractionally delayed copies of equally long responses in the frequency
// domain (a linear phase per bin: exact for band-limited signals, no interpolation filter
// to design). The transform is zero-padded to at least twice the longer of input and
// output, so a delay within (-input_length, output_length - input_length] does not wrap
// round into the kept samples.
class DelayingSum {
 public:
  DelayingSum(std::size_t input_length, std::size_t output_length);

  // Adds weight * response(t - delay_samples). `response` has input_length samples.
  void add(const std::vector<float>& response, double weight, double delay_samples);
  // The first output_length samples of the sum; clears the sum for the next one.
  std::vector<float> take();

 private:
  std::size_t input_length_;
  std::size_t output_length_;
  RealFft fft_;
  std::vector<float> time_;
  std::vector<std::complex<float>> spectrum_;
  std::vector<std::complex<double>> sum_;
};

}  // namespace room_reverb::core::hrir_timing
