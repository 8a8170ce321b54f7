#include "room_reverb/binaural/binaural_cues.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr std::size_t kUpsampling = 16;
constexpr double kMaxItdS = 1e-3;
// The ILD spectra are zero-padded to at least this many points so that even the 500 Hz
// octave spans a few dozen bins of a short filter.
constexpr std::size_t kMinIldFftSize = 4096;

void checkPair(const Hrir& pair) {
  if (pair.left.empty() || pair.left.size() != pair.right.size()) {
    throw InputError("an interaural cue needs a left and a right response of one non-zero length");
  }
}

std::vector<std::complex<float>> paddedSpectrum(RealFft& fft, const std::vector<float>& x) {
  std::vector<float> padded(fft.size(), 0.0f);
  std::copy(x.begin(), x.end(), padded.begin());
  return fft.forward(padded);
}

}  // namespace

double interauralTimeDifferenceS(const Hrir& pair, double sample_rate_hz, double max_frequency_hz) {
  checkPair(pair);
  RealFft fft(nextFastFftSize(2 * pair.left.size()));
  const auto left = paddedSpectrum(fft, pair.left);
  const auto right = paddedSpectrum(fft, pair.right);
  // Cross-spectrum of the low-passed pair, zero-padded in frequency to interpolate the
  // cross-correlation kUpsampling times finer. DC carries no lag and is left out: with it
  // a finite pair's correlation sits on a triangle that pulls the peak towards zero lag.
  RealFft fine(fft.size() * kUpsampling);
  std::vector<std::complex<float>> cross(fine.spectrumSize(), 0.0f);
  const double bin_hz = sample_rate_hz / static_cast<double>(fft.size());
  for (std::size_t k = 1; k < left.size() && static_cast<double>(k) * bin_hz <= max_frequency_hz; ++k) {
    cross[k] = left[k] * std::conj(right[k]);
  }
  const std::vector<float> correlation = fine.inverse(cross);
  // correlation[j] = sum_n l[n + j] r[n] at lag j / kUpsampling samples (negative lags wrap
  // to the end); the right ear lagging by d puts the peak at lag -d.
  const auto max_lag = static_cast<std::ptrdiff_t>(std::ceil(kMaxItdS * sample_rate_hz * kUpsampling));
  const auto size = static_cast<std::ptrdiff_t>(correlation.size());
  const auto at = [&](std::ptrdiff_t lag) { return correlation[static_cast<std::size_t>((lag + size) % size)]; };
  std::ptrdiff_t best = -max_lag;
  for (std::ptrdiff_t lag = -max_lag; lag <= max_lag; ++lag) {
    if (at(lag) > at(best)) best = lag;
  }
  const double before = at(best - 1), peak = at(best), after = at(best + 1);
  const double curvature = before - 2.0 * peak + after;
  const double offset = curvature < 0.0 ? 0.5 * (before - after) / curvature : 0.0;
  return -(static_cast<double>(best) + offset) / (kUpsampling * sample_rate_hz);
}

std::vector<double> interauralLevelDifferencesDb(const Hrir& pair, double sample_rate_hz,
                                                 const std::vector<FrequencyBand>& bands) {
  checkPair(pair);
  RealFft fft(nextFastFftSize(std::max(kMinIldFftSize, pair.left.size())));
  const auto left = paddedSpectrum(fft, pair.left);
  const auto right = paddedSpectrum(fft, pair.right);
  const BandFilterBank bank(bands, sample_rate_hz);
  std::vector<double> ild(bands.size(), 0.0);
  for (std::size_t b = 0; b < bands.size(); ++b) {
    if (!bank.bandBelowNyquist(b)) continue;
    double energy_left = 0.0, energy_right = 0.0;
    for (std::size_t k = 0; k < left.size(); ++k) {
      const double gain = bank.gain(b, sample_rate_hz * static_cast<double>(k) / static_cast<double>(fft.size()));
      energy_left += gain * gain * std::norm(left[k]);
      energy_right += gain * gain * std::norm(right[k]);
    }
    constexpr double kFloor = 1e-30;  // silence in a band gives a finite, large ILD
    ild[b] = 10.0 * std::log10((energy_left + kFloor) / (energy_right + kFloor));
  }
  return ild;
}

}  // namespace room_reverb::core
