#include "room_reverb/audio/convolution.h"

#include "room_reverb/audio/fft.h"

namespace room_reverb::core {

std::vector<float> fftConvolve(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.empty() || b.empty()) return {};
  const std::size_t out_size = a.size() + b.size() - 1;
  RealFft fft(nextFastFftSize(out_size));
  std::vector<float> padded(fft.size(), 0.0f);
  std::copy(a.begin(), a.end(), padded.begin());
  std::vector<std::complex<float>> spectrum_a = fft.forward(padded);
  std::fill(padded.begin(), padded.end(), 0.0f);
  std::copy(b.begin(), b.end(), padded.begin());
  const std::vector<std::complex<float>> spectrum_b = fft.forward(padded);
  for (std::size_t k = 0; k < spectrum_a.size(); ++k) spectrum_a[k] *= spectrum_b[k];
  std::vector<float> out = fft.inverse(spectrum_a);
  out.resize(out_size);
  return out;
}

}  // namespace room_reverb::core
