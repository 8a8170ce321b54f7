#include "hrir_timing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace room_reverb::core::hrir_timing {
namespace {

constexpr std::size_t kOnsetOversampling = 8;

}  // namespace

double onsetSamples(const std::vector<float>& response, double threshold_db) {
  if (response.empty()) return 0.0;
  // Zero padding to twice the length keeps the tail's circular wrap away from the start.
  RealFft fft(nextFastFftSize(2 * response.size()));
  std::vector<float> padded(fft.size(), 0.0f);
  std::copy(response.begin(), response.end(), padded.begin());
  const std::vector<std::complex<float>> spectrum = fft.forward(padded);

  // The same bins in a transform kOnsetOversampling times longer interpolate the waveform
  // band-limitedly (the scale does not matter: the threshold is relative to the peak).
  RealFft fine_fft(fft.size() * kOnsetOversampling);
  std::vector<std::complex<float>> fine_spectrum(fine_fft.spectrumSize(), 0.0f);
  std::copy(spectrum.begin(), spectrum.end(), fine_spectrum.begin());
  const std::vector<float> fine = fine_fft.inverse(fine_spectrum);

  const std::size_t span = response.size() * kOnsetOversampling;
  float peak = 0.0f;
  for (std::size_t n = 0; n < span; ++n) peak = std::max(peak, std::abs(fine[n]));
  if (peak <= 0.0f) return 0.0;
  const double threshold = peak * std::pow(10.0, -threshold_db / 20.0);
  for (std::size_t n = 0; n < span; ++n) {
    const double here = std::abs(fine[n]);
    if (here < threshold) continue;
    if (n == 0) return 0.0;
    const double before = std::abs(fine[n - 1]);
    const double fraction = (threshold - before) / (here - before);
    return (static_cast<double>(n - 1) + fraction) / kOnsetOversampling;
  }
  return 0.0;  // unreachable: the peak itself passes
}

DelayingSum::DelayingSum(std::size_t input_length, std::size_t output_length)
    : input_length_(input_length),
      output_length_(output_length),
      fft_(nextFastFftSize(2 * std::max<std::size_t>({input_length, output_length, 1}))),
      time_(fft_.size(), 0.0f),
      spectrum_(fft_.spectrumSize()),
      sum_(fft_.spectrumSize(), 0.0) {}

void DelayingSum::add(const std::vector<float>& response, double weight,
                      double delay_samples) {
  if (response.size() != input_length_) {
    throw std::invalid_argument("DelayingSum::add: response of the wrong length");
  }
  std::fill(time_.begin(), time_.end(), 0.0f);
  std::copy(response.begin(), response.end(), time_.begin());
  fft_.forward(time_.data(), spectrum_.data());
  const double radians_per_bin = -2.0 * M_PI * delay_samples / static_cast<double>(fft_.size());
  for (std::size_t k = 0; k < spectrum_.size(); ++k) {
    sum_[k] += weight * std::complex<double>(spectrum_[k]) *
               std::polar(1.0, radians_per_bin * static_cast<double>(k));
  }
  if (fft_.size() % 2 == 0) {
    // The Nyquist bin of a real signal must stay real: keep the real part of its phase
    // (cos(pi * delay)), the usual choice for a fractional delay there.
    const std::size_t nyquist = spectrum_.size() - 1;
    sum_[nyquist] = {sum_[nyquist].real(), 0.0};
  }
}

std::vector<float> DelayingSum::take() {
  for (std::size_t k = 0; k < sum_.size(); ++k) {
    spectrum_[k] = std::complex<float>(sum_[k]);
    sum_[k] = 0.0;
  }
  fft_.inverse(spectrum_.data(), time_.data());
  return std::vector<float>(time_.begin(), time_.begin() + static_cast<long>(output_length_));
}

}  // namespace room_reverb::core::hrir_timing
