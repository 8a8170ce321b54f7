#pragma once
// Linear convolution through the FFT.
#include <vector>

namespace room_reverb::core {

// Full linear convolution: a.size() + b.size() - 1 samples (empty if either is empty).
std::vector<float> fftConvolve(const std::vector<float>& a, const std::vector<float>& b);

}  // namespace room_reverb::core
