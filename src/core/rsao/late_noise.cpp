#include "room_reverb/rsao/late_noise.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <random>

#include <Eigen/Dense>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/rsao/late_envelope.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFs = kInternalSampleRateHz;

// Standard normal deviates by Box-Muller over mt19937 (fully specified), so a seed gives
// the same noise with any standard library.
class GaussianSource {
 public:
  explicit GaussianSource(std::uint32_t seed) : rng_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = (static_cast<double>(rng_()) + 0.5) / 4294967296.0;
    const double u2 = (static_cast<double>(rng_()) + 0.5) / 4294967296.0;
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(2.0 * kPi * u2);
    has_spare_ = true;
    return radius * std::cos(2.0 * kPi * u2);
  }

 private:
  std::mt19937 rng_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Centred moving average over `length` samples, the window shrinking at the ends.
std::vector<double> movingAverage(const std::vector<double>& x, std::size_t length) {
  const std::size_t n = x.size();
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + x[i];
  const std::size_t before = length / 2, after = length - 1 - before;
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t first = i >= before ? i - before : 0;
    const std::size_t last = std::min(n, i + after + 1);
    out[i] = (prefix[last] - prefix[first]) / static_cast<double>(last - first);
  }
  return out;
}

// Short-time mean square: two passes of a moving average (a triangular window).
std::vector<double> smoothed(const std::vector<double>& x, std::size_t length) {
  return movingAverage(movingAverage(x, length), length);
}

void normaliseMeanSquare(std::vector<float>& x) {
  double sum = 0.0;
  for (float v : x) sum += static_cast<double>(v) * v;
  if (!(sum > 0.0)) return;
  const auto gain = static_cast<float>(std::sqrt(static_cast<double>(x.size()) / sum));
  for (float& v : x) v *= gain;
}

// One band's noise: Gaussian bins shaped by the band's amplitude response `gain` (per
// bin), of unit mean square.
std::vector<float> bandNoise(const std::vector<double>& gain, RealFft& fft, GaussianSource& gaussian) {
  std::vector<std::complex<float>> spectrum(fft.spectrumSize());
  for (std::size_t k = 0; k < spectrum.size(); ++k) {
    const double re = gaussian(), im = gaussian();
    // DC and (for even sizes) Nyquist bins are real in a real signal's spectrum.
    const bool real_bin = k == 0 || (fft.size() % 2 == 0 && k + 1 == spectrum.size());
    spectrum[k] = std::complex<float>(static_cast<float>(gain[k] * re), real_bin ? 0.0f : static_cast<float>(gain[k] * im));
  }
  std::vector<float> noise(fft.size());
  fft.inverse(spectrum.data(), noise.data());
  normaliseMeanSquare(noise);
  return noise;
}

// How much of band noise b' each analysis band b sees: M(b, b') = sum_k |H_b(f_k)|^2
// |N_b'(f_k)|^2 / sum_k |N_b'(f_k)|^2 over the realised noise's spectrum. Adjacent bands of
// the bank overlap over their crossovers, so M is not diagonal: octave b' puts 5-9 % of its
// energy into each neighbour's analysis band.
Eigen::MatrixXd leakageMatrix(const std::vector<std::vector<float>>& noises,
                              const std::vector<std::vector<double>>& power_gain, RealFft& fft) {
  const auto bands = static_cast<Eigen::Index>(noises.size());
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(bands, bands);
  std::vector<std::complex<float>> spectrum(fft.spectrumSize());
  for (Eigen::Index source = 0; source < bands; ++source) {
    fft.forward(noises[static_cast<std::size_t>(source)].data(), spectrum.data());
    double total = 0.0;
    for (std::size_t k = 0; k < spectrum.size(); ++k) {
      const double power = std::norm(spectrum[k]);
      total += power;
      for (Eigen::Index b = 0; b < bands; ++b) m(b, source) += power_gain[static_cast<std::size_t>(b)][k] * power;
    }
    if (total > 0.0) m.col(source) /= total;
  }
  return m;
}

// The model's mean square of each analysis band over time (late_envelope.h).
std::vector<std::vector<double>> targetPowers(const LateReverb& late, std::size_t frames, OnsetRamp shape) {
  std::vector<std::vector<double>> target(late.bands.size(), std::vector<double>(frames));
  for (std::size_t b = 0; b < late.bands.size(); ++b) {
    for (std::size_t n = 0; n < frames; ++n) {
      const double amplitude = late.bands[b].level * lateEnvelopeGain(late, b, static_cast<double>(n) / kFs, shape);
      target[b][n] = amplitude * amplitude;
    }
  }
  return target;
}

std::vector<float> mix(const std::vector<std::vector<float>>& noises, const std::vector<std::vector<double>>& amplitude) {
  std::vector<float> x(amplitude.front().size(), 0.0f);
  for (std::size_t b = 0; b < noises.size(); ++b) {
    for (std::size_t n = 0; n < x.size(); ++n) x[n] += static_cast<float>(amplitude[b][n] * noises[b][n]);
  }
  return x;
}

// The envelope matching's smoothing length of a band, in samples: the longer of
// match_bandwidths / bandwidth and match_min_span_s.
std::size_t matchingSpan(const FrequencyBand& band, const ResynthesisOptions& o) {
  const double span_s = std::max(o.match_min_span_s, o.match_bandwidths / (band.upper_hz - band.lower_hz));
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(span_s * kFs)));
}

// One channel of the late part: band noises under amplitudes such that each analysis band
// of the result follows its target power.
//  1. Leakage: analysis band b sees its own noise and some of its neighbours', so the
//     powers are p = M^-1 target at every sample (zero where a band has decayed so far
//     below a neighbour that even silence would show more than its target).
//  2. Envelope matching: one Gaussian draw's envelope wanders (Rayleigh), in a narrow band
//     by enough to scatter its T20 by +-20 % (ISO 3382-2 A.2); and where bands overlap,
//     independent noises beat. So the result is analysed as the estimator will analyse it,
//     each band's short-time mean square (smoothed over the longer of match_bandwidths /
//     bandwidth and match_min_span_s) is compared with the target's, smoothed alike, and
//     the band's amplitude corrected by the root of the ratio; a few passes converge. Fine
//     structure shorter than that span stays noise. The floor on the span keeps the
//     corrections slow in the high bands: a gain varying within a millisecond would spread
//     a band's noise into its neighbours' analysis bands, the very leakage step 1 removes.
std::vector<float> shapeChannel(const BandFilterBank& bank, const std::vector<std::vector<double>>& target,
                                const std::vector<std::vector<float>>& noises,
                                const std::vector<std::vector<double>>& power_gain, RealFft& fft,
                                const ResynthesisOptions& o) {
  const std::size_t bands = target.size(), frames = target.front().size();
  const Eigen::MatrixXd unmix = leakageMatrix(noises, power_gain, fft).inverse();
  std::vector<std::vector<double>> amplitude(bands, std::vector<double>(frames));
  Eigen::VectorXd wanted(static_cast<Eigen::Index>(bands)), power(static_cast<Eigen::Index>(bands));
  for (std::size_t n = 0; n < frames; ++n) {
    for (std::size_t b = 0; b < bands; ++b) wanted(static_cast<Eigen::Index>(b)) = target[b][n];
    power.noalias() = unmix * wanted;
    for (std::size_t b = 0; b < bands; ++b) {
      amplitude[b][n] = std::sqrt(std::max(0.0, power(static_cast<Eigen::Index>(b))));
    }
  }

  std::vector<std::size_t> span(bands);
  std::vector<std::vector<double>> target_smoothed(bands);
  for (std::size_t b = 0; b < bands; ++b) {
    span[b] = matchingSpan(bank.bands()[b], o);
    target_smoothed[b] = smoothed(target[b], span[b]);
  }
  std::vector<double> view_power(frames);
  for (int pass = 0; pass < o.match_passes; ++pass) {
    const std::vector<std::vector<float>> views = bank.split(mix(noises, amplitude));
    for (std::size_t b = 0; b < bands; ++b) {
      for (std::size_t n = 0; n < frames; ++n) view_power[n] = static_cast<double>(views[b][n]) * views[b][n];
      const std::vector<double> seen = smoothed(view_power, span[b]);
      for (std::size_t n = 0; n < frames; ++n) {
        // Clamped so one pass never swings a gain by more than 20 dB.
        const double ratio = seen[n] > 0.0 ? std::clamp(target_smoothed[b][n] / seen[n], 0.01, 100.0) : 1.0;
        amplitude[b][n] *= std::sqrt(ratio);
      }
    }
  }
  return mix(noises, amplitude);
}

}  // namespace

struct LateNoiseSynthesizer::State {
  State(std::size_t frame_count, const ResynthesisOptions& o)
      : options(o),
        frames(frame_count),
        bank(standardBands(BandResolution::kOctave), kFs),
        fft(nextFastFftSize(frame_count)),
        gaussian(o.seed) {
    const std::size_t bands = bank.bands().size();
    gain.assign(bands, std::vector<double>(fft.spectrumSize()));
    power_gain = gain;
    for (std::size_t b = 0; b < bands; ++b) {
      for (std::size_t k = 0; k < fft.spectrumSize(); ++k) {
        gain[b][k] = bank.gain(b, static_cast<double>(k) * kFs / static_cast<double>(fft.size()));
        power_gain[b][k] = gain[b][k] * gain[b][k];
      }
    }
  }

  ResynthesisOptions options;
  std::size_t frames;
  BandFilterBank bank;
  RealFft fft;
  GaussianSource gaussian;
  std::vector<std::vector<double>> gain;        // per band and FFT bin: the band's amplitude response
  std::vector<std::vector<double>> power_gain;  // its square
};

LateNoiseSynthesizer::LateNoiseSynthesizer(std::size_t frames, const ResynthesisOptions& options)
    : state_(std::make_unique<State>(frames, options)) {}

LateNoiseSynthesizer::~LateNoiseSynthesizer() = default;

std::vector<std::vector<float>> LateNoiseSynthesizer::drawBandNoises() {
  std::vector<std::vector<float>> noises;
  for (const std::vector<double>& gain : state_->gain) noises.push_back(bandNoise(gain, state_->fft, state_->gaussian));
  return noises;
}

void LateNoiseSynthesizer::flattenEnvelopes(std::vector<std::vector<float>>& band_noises) const {
  for (std::size_t b = 0; b < band_noises.size(); ++b) {
    std::vector<float>& noise = band_noises[b];
    std::vector<double> power(noise.size());
    for (std::size_t n = 0; n < noise.size(); ++n) power[n] = static_cast<double>(noise[n]) * noise[n];
    const std::vector<double> local = smoothed(power, matchingSpan(state_->bank.bands()[b], state_->options));
    for (std::size_t n = 0; n < noise.size(); ++n) {
      if (local[n] > 0.0) noise[n] = static_cast<float>(noise[n] / std::sqrt(local[n]));
    }
  }
}

std::vector<std::vector<double>> LateNoiseSynthesizer::targetPowers(const LateReverb& late) const {
  return core::targetPowers(late, state_->frames, state_->options.onset_ramp);
}

std::vector<float> LateNoiseSynthesizer::shape(const std::vector<std::vector<double>>& target,
                                               const std::vector<std::vector<float>>& band_noises) {
  return shapeChannel(state_->bank, target, band_noises, state_->power_gain, state_->fft, state_->options);
}

}  // namespace room_reverb::core
