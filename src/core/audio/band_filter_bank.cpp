#include "room_reverb/audio/band_filter_bank.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "room_reverb/audio/fft.h"

namespace room_reverb::core {
namespace {

constexpr double kHalfPi = 1.57079632679489661923;

// Fraction of the way through a crossover centred on `edge_log2` of width `width`, 0 below
// it and 1 above it.
double crossoverPosition(double f_log2, double edge_log2, double width) {
  return std::clamp((f_log2 - (edge_log2 - 0.5 * width)) / width, 0.0, 1.0);
}

}  // namespace

BandFilterBank::BandFilterBank(std::vector<FrequencyBand> bands, double sample_rate_hz,
                               double crossover_fraction)
    : bands_(std::move(bands)), sample_rate_hz_(sample_rate_hz) {
  if (bands_.empty()) throw std::invalid_argument("BandFilterBank needs at least one band");
  if (!(crossover_fraction > 0.0 && crossover_fraction <= 1.0)) {
    throw std::invalid_argument("BandFilterBank crossover fraction must be in (0, 1]");
  }
  const double band_octaves = std::log2(bands_.front().upper_hz / bands_.front().lower_hz);
  crossover_octaves_ = crossover_fraction * band_octaves;
}

bool BandFilterBank::bandBelowNyquist(std::size_t band) const {
  return bands_.at(band).center_hz < 0.5 * sample_rate_hz_;
}

double BandFilterBank::gain(std::size_t band, double frequency_hz) const {
  if (frequency_hz <= 0.0) return 0.0;
  const FrequencyBand& b = bands_.at(band);
  const double f = std::log2(frequency_hz);
  // Rising (sin) crossover at the lower edge, falling (cos) one at the upper edge: the
  // upper band's sin and this band's cos at a shared edge are power complementary.
  const double rise = std::sin(kHalfPi * crossoverPosition(f, std::log2(b.lower_hz), crossover_octaves_));
  const double fall = std::cos(kHalfPi * crossoverPosition(f, std::log2(b.upper_hz), crossover_octaves_));
  return rise * fall;
}

std::vector<std::vector<float>> BandFilterBank::split(const std::vector<float>& signal) const {
  std::vector<std::vector<float>> out(bands_.size());
  if (signal.empty()) return out;
  RealFft fft(nextFastFftSize(2 * signal.size()));
  std::vector<float> padded(fft.size(), 0.0f);
  std::copy(signal.begin(), signal.end(), padded.begin());
  const std::vector<std::complex<float>> spectrum = fft.forward(padded);

  std::vector<std::complex<float>> band_spectrum(spectrum.size());
  const double bin_hz = sample_rate_hz_ / static_cast<double>(fft.size());
  for (std::size_t b = 0; b < bands_.size(); ++b) {
    if (!bandBelowNyquist(b)) {
      out[b].assign(signal.size(), 0.0f);
      continue;
    }
    // Only bins inside the band's support need work; the rest are zero.
    const double low = bands_[b].lower_hz * std::pow(2.0, -0.5 * crossover_octaves_);
    const double high = bands_[b].upper_hz * std::pow(2.0, 0.5 * crossover_octaves_);
    std::fill(band_spectrum.begin(), band_spectrum.end(), std::complex<float>(0.0f, 0.0f));
    const auto first = static_cast<std::size_t>(std::floor(low / bin_hz));
    const auto last = std::min(spectrum.size() - 1, static_cast<std::size_t>(std::ceil(high / bin_hz)));
    for (std::size_t k = first; k <= last; ++k) {
      band_spectrum[k] = spectrum[k] * static_cast<float>(gain(b, k * bin_hz));
    }
    std::vector<float> band_signal = fft.inverse(band_spectrum);
    band_signal.resize(signal.size());
    out[b] = std::move(band_signal);
  }
  return out;
}

}  // namespace room_reverb::core
