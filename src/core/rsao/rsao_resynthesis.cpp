#include "room_reverb/rsao/rsao_resynthesis.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <random>
#include <string>

#include <Eigen/Dense>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/analysis_window.h"
#include "room_reverb/rsao/late_envelope.h"
#include "room_reverb/rsao/lpc.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFs = kInternalSampleRateHz;
constexpr int kKernelHalfLength = 16;  // fractional-delay taps either side of the arrival
constexpr double kMaxDurationS = 60.0;

// A section's poles lie inside the unit circle iff (a1, a2) is inside the stability
// triangle |a2| < 1, |a1| < 1 + a2.
bool sectionsStable(const std::vector<BiquadSection>& sections) {
  for (const BiquadSection& s : sections) {
    if (!(std::abs(s.a2) < 1.0 && std::abs(s.a1) < 1.0 + s.a2)) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------
// Early part
// ---------------------------------------------------------------------------------------

// Blackman-windowed sinc interpolating a unit pulse at `fraction` (in [0, 1)) of a sample
// past sample 0; tap i is for sample offset i - kKernelHalfLength + 1.
std::vector<double> fractionalDelayKernel(double fraction) {
  std::vector<double> kernel(2 * kKernelHalfLength);
  for (std::size_t i = 0; i < kernel.size(); ++i) {
    const double x = static_cast<double>(i) - (kKernelHalfLength - 1) - fraction;  // in (-H, H]
    const double sinc = std::abs(x) < 1e-12 ? 1.0 : std::sin(kPi * x) / (kPi * x);
    const double u = x / kKernelHalfLength;
    const double window = 0.42 + 0.5 * std::cos(kPi * u) + 0.08 * std::cos(2.0 * kPi * u);
    kernel[i] = sinc * window;
  }
  return kernel;
}

Eigen::Vector3d unitDirection(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

std::string reflectionName(std::size_t k) {
  return k == 0 ? std::string("the direct sound") : "reflection " + std::to_string(k);
}

void addReflection(const EarlyReflection& r, std::size_t k, const ResynthesisOptions& o, AudioBuffer& out) {
  if (r.level == 0.0) return;
  const double position = r.time_of_arrival_s * kFs;
  const double whole = std::floor(position);
  std::vector<double> tap = fractionalDelayKernel(position - whole);
  tap.resize(tap.size() + static_cast<std::size_t>(std::lround(o.reflection_response_s * kFs)), 0.0);
  if (!r.sos.empty()) {
    if (!sectionsStable(r.sos)) throw InputError("resynthesis: " + reflectionName(k) + " has an unstable second-order section");
    tap = filterSections(r.sos, tap);
  } else if (r.lpc.size() > 1) {
    tap = filterAllPole(r.lpc, r.lpc_gain, tap);
    const std::size_t eighth = tap.size() / 8;
    double head = 0.0, tail = 0.0;
    for (std::size_t i = 0; i < eighth; ++i) {
      head += tap[i] * tap[i];
      tail += tap[tap.size() - 1 - i] * tap[tap.size() - 1 - i];
    }
    if (!std::isfinite(tail) || tail > head) {
      throw InputError("resynthesis: " + reflectionName(k) + "'s LPC filter is unstable (its response grows)");
    }
  }
  // Scale: the W energy under the estimator's own window (a Hamming window of length D
  // centred on the arrival, analysis_window.h) is level^2, so that estimating this tap
  // again gives back its level.
  const double centre = static_cast<double>(kKernelHalfLength - 1) + (position - whole);
  const SampleWindow window = hammingWindowAt(centre, o.analysis_window_s * kFs, tap.size());
  double energy = 0.0;
  for (std::size_t i = 0; i < window.weights.size(); ++i) {
    const double v = window.weights[i] * tap[window.first + i];
    energy += v * v;
  }
  if (!(energy > 0.0)) return;  // a filter that is zero over the window: nothing to place
  const double gain = r.level / std::sqrt(energy);

  const std::vector<double> harmonics = sn3dHarmonics(1, unitDirection(r.azimuth_rad, r.elevation_rad));
  const long start = static_cast<long>(whole) - (kKernelHalfLength - 1);
  for (std::size_t i = 0; i < tap.size(); ++i) {
    const long n = start + static_cast<long>(i);
    if (n < 0) continue;
    if (static_cast<std::size_t>(n) >= out.frameCount()) break;
    for (std::size_t c = 0; c < 4; ++c) {
      out.channels[c][static_cast<std::size_t>(n)] += static_cast<float>(gain * harmonics[c] * tap[i]);
    }
  }
}

// ---------------------------------------------------------------------------------------
// Late part
// ---------------------------------------------------------------------------------------

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
std::vector<float> lateChannel(const BandFilterBank& bank, const std::vector<std::vector<double>>& target,
                               const std::vector<std::vector<double>>& gain,
                               const std::vector<std::vector<double>>& power_gain, RealFft& fft,
                               GaussianSource& gaussian, const ResynthesisOptions& o) {
  const std::size_t bands = target.size(), frames = target.front().size();
  std::vector<std::vector<float>> noises;
  for (std::size_t b = 0; b < bands; ++b) noises.push_back(bandNoise(gain[b], fft, gaussian));

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
    const FrequencyBand& band = bank.bands()[b];
    const double span_s = std::max(o.match_min_span_s, o.match_bandwidths / (band.upper_hz - band.lower_hz));
    span[b] = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(span_s * kFs)));
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

void addLateReverb(const LateReverb& late, const ResynthesisOptions& o, AudioBuffer& out) {
  const BandFilterBank bank(standardBands(BandResolution::kOctave), kFs);
  const std::size_t frames = out.frameCount();
  const std::size_t bands = late.bands.size();
  RealFft fft(nextFastFftSize(frames));
  GaussianSource gaussian(o.seed);
  const std::vector<std::vector<double>> target = targetPowers(late, frames, o.onset_ramp);
  std::vector<std::vector<double>> gain(bands, std::vector<double>(fft.spectrumSize()));
  std::vector<std::vector<double>> power_gain = gain;
  for (std::size_t b = 0; b < bands; ++b) {
    for (std::size_t k = 0; k < fft.spectrumSize(); ++k) {
      gain[b][k] = bank.gain(b, static_cast<double>(k) * kFs / static_cast<double>(fft.size()));
      power_gain[b][k] = gain[b][k] * gain[b][k];
    }
  }
  // Diffuse field in SN3D: E[X^2] = E[Y^2] = E[Z^2] = E[W^2] / 3, all mutually uncorrelated.
  const double channel_gain[4] = {1.0, 1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)};
  for (std::size_t c = 0; c < 4; ++c) {
    const std::vector<float> x = lateChannel(bank, target, gain, power_gain, fft, gaussian, o);
    for (std::size_t n = 0; n < frames; ++n) out.channels[c][n] += static_cast<float>(channel_gain[c] * x[n]);
  }
}

// ---------------------------------------------------------------------------------------
// Checks and length
// ---------------------------------------------------------------------------------------

bool finiteNonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

void checkRsao(const Rsao& r) {
  for (std::size_t k = 0; k < r.reflections.size(); ++k) {
    const EarlyReflection& e = r.reflections[k];
    if (!finiteNonNegative(e.time_of_arrival_s) || !finiteNonNegative(e.level) || !std::isfinite(e.azimuth_rad) ||
        !std::isfinite(e.elevation_rad)) {
      throw InputError("resynthesis: " + reflectionName(k) +
                       " needs a finite, non-negative time of arrival and level and a finite direction");
    }
  }
  const LateReverb& late = r.late;
  if (late.bands.empty()) return;
  if (late.bands.size() != static_cast<std::size_t>(kOctaveBandCount)) {
    throw InputError("resynthesis: the late reverb has " + std::to_string(late.bands.size()) +
                     " bands; it needs the nine octave bands 63 Hz .. 16 kHz");
  }
  if (!finiteNonNegative(late.onset_s) || !finiteNonNegative(late.mixing_time_s) || late.onset_s > late.mixing_time_s) {
    throw InputError("resynthesis: the late onset must be finite, non-negative and no later than the mixing time");
  }
  for (const LateReverbBand& band : late.bands) {
    if (!(std::isfinite(band.decay_constant_per_s) && band.decay_constant_per_s > 0.0) || !finiteNonNegative(band.level) ||
        !finiteNonNegative(band.onset_level)) {
      throw InputError("resynthesis: the late band at " + std::to_string(static_cast<int>(std::lround(band.center_hz))) +
                       " Hz needs a positive decay constant and a non-negative level and onset level");
    }
  }
}

double defaultDuration(const Rsao& r, const ResynthesisOptions& o) {
  if (r.duration_s > 0.0) return r.duration_s;
  double end = 0.0;
  for (const EarlyReflection& e : r.reflections) end = std::max(end, e.time_of_arrival_s + o.reflection_response_s);
  for (const LateReverbBand& band : r.late.bands) {
    end = std::max(end, r.late.mixing_time_s + 3.0 * std::log(10.0) / band.decay_constant_per_s);  // the band's T60
  }
  return end;
}

}  // namespace

AudioBuffer resynthesizeRsao(const Rsao& rsao, const ResynthesisOptions& options) {
  checkRsao(rsao);
  if (!(options.analysis_window_s > 0.0 && options.reflection_response_s >= 0.0 && options.match_bandwidths > 0.0 &&
        options.match_passes >= 0)) {
    throw InputError("resynthesis: analysis_window_s and match_bandwidths must be positive, match_passes not negative");
  }
  const double duration = options.duration_s > 0.0 ? options.duration_s : defaultDuration(rsao, options);
  if (!(duration > 0.0 && duration <= kMaxDurationS)) {
    char text[64];
    std::snprintf(text, sizeof text, "%.4g", duration);
    throw InputError(std::string("resynthesis: the output would last ") + text + " s; give duration_s in (0, 60]");
  }
  AudioBuffer out = makeSilentBuffer(4, static_cast<std::size_t>(std::lround(duration * kFs)), kFs);
  if (options.include_early) {
    for (std::size_t k = 0; k < rsao.reflections.size(); ++k) addReflection(rsao.reflections[k], k, options, out);
  }
  if (options.include_late && !rsao.late.bands.empty()) addLateReverb(rsao.late, options, out);
  return out;
}

}  // namespace room_reverb::core
