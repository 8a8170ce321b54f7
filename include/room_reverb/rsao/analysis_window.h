#pragma once
// The analysis window of the RSAO estimator: a Hamming window of length D centred on an
// arrival time that need not fall on a sample (Remaggi et al. section 2.1 take level,
// direction and spectrum of each reflection over such a window).
#include <cstddef>
#include <vector>

namespace room_reverb::core {

struct SampleWindow {
  std::size_t first = 0;        // index of the first sample the window covers
  std::vector<double> weights;  // weights[i] applies to sample first + i
};

// w(t) = 0.54 + 0.46 cos(2 pi t / D) for |t| <= D/2, t = n - centre_sample, evaluated at the
// samples n of [0, signal_length) inside the support (so a fractional centre shifts the
// weights, not the arrival). Samples outside the signal are left out (taken as zero).
SampleWindow hammingWindowAt(double centre_sample, double length_samples, std::size_t signal_length);

}  // namespace room_reverb::core
