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

// sin(pi/2 p) for p in [0, 1] from a table with linear interpolation: within 2e-8, below
// the resolution of the single-precision gains it is used for. The exact gain per bin (a
// log2, a sine and a cosine) costs 9 % of an RSAO estimate (perf), and the crossovers
// hold half the bins of a split.
constexpr int kQuarterSineSteps = 4096;
const std::vector<double> kQuarterSine = [] {
  std::vector<double> t(kQuarterSineSteps + 2);
  for (int i = 0; i <= kQuarterSineSteps + 1; ++i) {
    t[static_cast<std::size_t>(i)] = std::sin(kHalfPi * std::min(1.0, static_cast<double>(i) / kQuarterSineSteps));
  }
  return t;
}();

inline double quarterSine(double p) {
  const double x = p * kQuarterSineSteps;  // p is a crossoverPosition: in [0, 1]
  const auto i = static_cast<std::size_t>(x);
  const double f = x - static_cast<double>(i);
  return kQuarterSine[i] + f * (kQuarterSine[i + 1] - kQuarterSine[i]);
}

}  // namespace

BandFilterBank::BandFilterBank(std::vector<FrequencyBand> bands, double sample_rate_hz,
                               double crossover_fraction, Complementarity complementarity)
    : bands_(std::move(bands)), sample_rate_hz_(sample_rate_hz), complementarity_(complementarity) {
  if (bands_.empty()) throw std::invalid_argument("BandFilterBank needs at least one band");
  if (!(crossover_fraction > 0.0 && crossover_fraction <= 1.0)) {
    throw std::invalid_argument("BandFilterBank crossover fraction must be in (0, 1]");
  }
  // Each edge's crossover width: a fraction of the band's width, and at an edge shared by
  // two bands of different widths (octaves next to thirds) of the narrower one, the same
  // from both sides so the pair stays power complementary.
  const std::size_t count = bands_.size();
  lower_crossover_octaves_.resize(count);
  upper_crossover_octaves_.resize(count);
  for (std::size_t b = 0; b < count; ++b) {
    const double width = std::log2(bands_[b].upper_hz / bands_[b].lower_hz);
    lower_crossover_octaves_[b] = crossover_fraction * width;
    upper_crossover_octaves_[b] = crossover_fraction * width;
  }
  for (std::size_t b = 0; b + 1 < count; ++b) {
    if (std::abs(std::log2(bands_[b].upper_hz / bands_[b + 1].lower_hz)) > 1e-9) continue;
    const double shared = std::min(upper_crossover_octaves_[b], lower_crossover_octaves_[b + 1]);
    upper_crossover_octaves_[b] = shared;
    lower_crossover_octaves_[b + 1] = shared;
  }
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
  const double rise = std::sin(kHalfPi * crossoverPosition(f, std::log2(b.lower_hz), lower_crossover_octaves_[band]));
  const double fall = std::cos(kHalfPi * crossoverPosition(f, std::log2(b.upper_hz), upper_crossover_octaves_[band]));
  const double amplitude = rise * fall;
  return complementarity_ == Complementarity::kPower ? amplitude : amplitude * amplitude;
}

BandFilterBank::PaddedSpectrum BandFilterBank::analyse(const std::vector<float>& signal) const {
  PaddedSpectrum out;
  out.signal_length = signal.size();
  if (signal.empty()) return out;
  RealFft fft(nextFastFftSize(2 * signal.size()));
  std::vector<float> padded(fft.size(), 0.0f);
  std::copy(signal.begin(), signal.end(), padded.begin());
  out.fft_size = fft.size();
  out.bins = fft.forward(padded);
  return out;
}

void BandFilterBank::fillBandSpectrum(const PaddedSpectrum& spectrum, std::size_t band,
                                      std::vector<std::complex<float>>& out, std::size_t shift) const {
  const double bin_hz = sample_rate_hz_ / static_cast<double>(spectrum.fft_size);
  std::fill(out.begin(), out.end(), std::complex<float>(0.0f, 0.0f));
  // Only bins inside the band's support need work; the rest are zero.
  const auto [first, last] = supportBins(spectrum, band);
  // Between the crossovers the gain is exactly one; the logarithm and the trigonometry are
  // spent on the crossovers' bins only.
  const double lower_log2 = std::log2(bands_[band].lower_hz);
  const double upper_log2 = std::log2(bands_[band].upper_hz);
  const double flat_low = bands_[band].lower_hz * std::pow(2.0, 0.5 * lower_crossover_octaves_[band]);
  const double flat_high = bands_[band].upper_hz * std::pow(2.0, -0.5 * upper_crossover_octaves_[band]);
  for (std::size_t k = std::max<std::size_t>({first, shift, 1}); k <= last && k - shift < out.size(); ++k) {
    const double f = k * bin_hz;
    if (f > flat_low && f < flat_high) {
      out[k - shift] = spectrum.bins[k];
      continue;
    }
    // In one crossover or the other: the rise sin(pi/2 p) or the fall cos(pi/2 q) =
    // sin(pi/2 (1 - q)), as gain() has them.
    const double f_log2 = std::log2(f);
    const double amplitude =
        f <= flat_low ? quarterSine(crossoverPosition(f_log2, lower_log2, lower_crossover_octaves_[band]))
                      : quarterSine(1.0 - crossoverPosition(f_log2, upper_log2, upper_crossover_octaves_[band]));
    out[k - shift] = spectrum.bins[k] * static_cast<float>(complementarity_ == Complementarity::kPower ? amplitude : amplitude * amplitude);
  }
}

std::pair<std::size_t, std::size_t> BandFilterBank::supportBins(const PaddedSpectrum& spectrum, std::size_t band) const {
  const double bin_hz = sample_rate_hz_ / static_cast<double>(spectrum.fft_size);
  const double low = bands_[band].lower_hz * std::pow(2.0, -0.5 * lower_crossover_octaves_[band]);
  const double high = bands_[band].upper_hz * std::pow(2.0, 0.5 * upper_crossover_octaves_[band]);
  const auto first = static_cast<std::size_t>(std::floor(low / bin_hz));
  const auto last = std::min(spectrum.bins.size() - 1, static_cast<std::size_t>(std::ceil(high / bin_hz)));
  return {first, last};
}

std::vector<float> BandFilterBank::extract(const PaddedSpectrum& spectrum, std::size_t band) const {
  if (spectrum.signal_length == 0) return {};
  if (!bandBelowNyquist(band)) return std::vector<float>(spectrum.signal_length, 0.0f);
  RealFft fft(spectrum.fft_size);
  std::vector<std::complex<float>> band_spectrum(spectrum.bins.size());
  fillBandSpectrum(spectrum, band, band_spectrum);
  std::vector<float> band_signal = fft.inverse(band_spectrum);
  band_signal.resize(spectrum.signal_length);
  return band_signal;
}

BandFilterBank::BandEnergy BandFilterBank::extractEnergyEnvelope(const PaddedSpectrum& spectrum, std::size_t band,
                                                                 double min_rate_hz, double width_oversampling) const {
  if (!(width_oversampling >= 1.0)) throw std::invalid_argument("BandFilterBank: width oversampling must be at least 1");
  if (!(min_rate_hz >= 0.0)) throw std::invalid_argument("BandFilterBank: the minimum rate must not be negative");
  BandEnergy out;
  out.sample_rate_hz = sample_rate_hz_;
  if (spectrum.signal_length == 0) return out;
  if (!bandBelowNyquist(band)) {
    out.energy.assign(spectrum.signal_length, 0.0);
    return out;
  }
  const std::size_t n = spectrum.fft_size;
  const auto [first, last] = supportBins(spectrum, band);
  const double bin_hz = sample_rate_hz_ / static_cast<double>(n);
  // m bins of the baseband transform span m * bin_hz: the rate of its samples.
  const std::size_t width = last - first + 1;
  const auto wanted = static_cast<std::size_t>(std::ceil(std::max(width_oversampling * static_cast<double>(width),
                                                                  min_rate_hz / bin_hz)));
  const std::size_t m = std::min(nextFastFftSize(std::max(width, wanted)), nextFastFftSize(n));
  // The analytic signal's spectrum is twice the positive bins (the Nyquist bin, shared by
  // both halves, once), shifted down by `first` bins: that only turns the phase of z(t),
  // not its magnitude.
  std::vector<std::complex<float>> baseband(m);
  fillBandSpectrum(spectrum, band, baseband, first);
  for (std::size_t k = first; k <= last && k - first < m; ++k) baseband[k - first] *= (2 * k == n) ? 1.0f : 2.0f;
  std::vector<std::complex<float>> z(m);
  ComplexInverseFft(m).inverse(baseband.data(), z.data());
  // The input's inverse scales by 1 / n; each sample then stands for n / m input samples.
  const double scale = 0.5 / (static_cast<double>(n) * static_cast<double>(n));
  out.sample_rate_hz = bin_hz * static_cast<double>(m);
  const auto length = static_cast<std::size_t>(
      std::ceil(static_cast<double>(spectrum.signal_length) * static_cast<double>(m) / static_cast<double>(n)));
  out.energy.resize(std::min(length, m));
  for (std::size_t i = 0; i < out.energy.size(); ++i) out.energy[i] = scale * std::norm(std::complex<double>(z[i]));
  return out;
}

std::vector<std::vector<float>> BandFilterBank::split(const std::vector<float>& signal) const {
  const PaddedSpectrum spectrum = analyse(signal);
  std::vector<std::vector<float>> out(bands_.size());
  for (std::size_t b = 0; b < bands_.size(); ++b) out[b] = extract(spectrum, b);
  return out;
}

}  // namespace room_reverb::core
