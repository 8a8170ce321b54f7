#include "room_reverb/rsao/echo_density.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/common/error.h"
#include "../common/simd_clones.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

// erfc(1/sqrt 2): the share of a Gaussian's samples farther than one standard deviation
// from the mean, the normaliser that makes Gaussian noise read eta = 1.
const double kGaussianShareAboveSigma = std::erfc(1.0 / std::sqrt(2.0));

// Window weights of odd length, summing to one. The Hann form leaves out its zero end
// points (they would only waste two taps).
std::vector<double> windowWeights(std::size_t length, EchoDensityWindow shape) {
  std::vector<double> w(length, 1.0);
  if (shape == EchoDensityWindow::kHann) {
    for (std::size_t k = 0; k < length; ++k) {
      w[k] = 0.5 * (1.0 - std::cos(2.0 * kPi * static_cast<double>(k + 1) / static_cast<double>(length + 1)));
    }
  }
  double sum = 0.0;
  for (double v : w) sum += v;
  for (double& v : w) v /= sum;
  return w;
}

void checkOptions(const EchoDensityOptions& options, double fs) {
  if (!(fs > 0.0)) throw InputError("echo density: the sample rate must be positive");
  if (!(options.window_s >= 0.001 && options.window_s <= 1.0)) {
    throw InputError("echo density: window_s must be between 0.001 and 1 s (Abel & Huang use 0.020)");
  }
  if (!(options.hop_s > 0.0 && options.hop_s <= options.window_s)) {
    throw InputError("echo density: hop_s must be positive and no longer than the window");
  }
}

std::string text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

}  // namespace

namespace detail {
// One window of the profile: the weighted mean square of `x2` (squared samples) and the
// weight of the samples above it. Single precision, eight partial sums per quantity: the
// loops then run eight lanes wide where the CPU has AVX2 (the profile reads every sample
// about window / hop = 80 times, which makes this the mixing-time estimate's whole cost).
// A window's sum of 961 weighted squares in eight float lanes is exact to about 1e-6 of
// itself, far inside the count's own statistical spread.
ROOM_REVERB_SIMD_CLONES
double windowShareAboveSigma(const float* x2, const float* w, std::size_t length, double& mean_square) {
  constexpr std::size_t kLanes = 8;
  const std::size_t blocked = length - length % kLanes;
  float partial[kLanes] = {};
  for (std::size_t k = 0; k < blocked; k += kLanes) {
    for (std::size_t j = 0; j < kLanes; ++j) partial[j] += w[k + j] * x2[k + j];
  }
  for (std::size_t k = blocked; k < length; ++k) partial[k % kLanes] += w[k] * x2[k];
  double sum = 0.0;
  for (float p : partial) sum += p;
  mean_square = sum;
  // |x| > sigma, compared as x^2 > sigma^2 = mean_square.
  if (!(mean_square > 0.0)) return 0.0;
  const auto threshold = static_cast<float>(mean_square);
  float counted[kLanes] = {};
  for (std::size_t k = 0; k < blocked; k += kLanes) {
    for (std::size_t j = 0; j < kLanes; ++j) counted[j] += x2[k + j] > threshold ? w[k + j] : 0.0f;
  }
  for (std::size_t k = blocked; k < length; ++k) counted[k % kLanes] += x2[k] > threshold ? w[k] : 0.0f;
  double share = 0.0;
  for (float c : counted) share += c;
  return share;
}
}  // namespace detail

EchoDensityProfile echoDensityProfile(const std::vector<float>& rir, double fs,
                                      const EchoDensityOptions& options) {
  checkOptions(options, fs);
  const auto half = static_cast<std::size_t>(std::lround(0.5 * options.window_s * fs));
  const std::size_t length = 2 * half + 1;
  if (rir.size() < length) {
    throw InputError("echo density: the RIR (" + std::to_string(rir.size()) +
                     " samples) is shorter than one analysis window (" + std::to_string(length) + ")");
  }
  if (!allSamplesFinite(rir)) throw InputError("echo density: the RIR holds a non-finite sample");
  const std::vector<double> w = windowWeights(length, options.window);
  const auto hop = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(options.hop_s * fs)));

  EchoDensityProfile profile;
  profile.sample_rate_hz = fs;
  double sum_of_squared_weights = 0.0;
  for (double v : w) sum_of_squared_weights += v * v;
  // The count is taken against the window's own sigma, which rises with the samples it
  // counts; to first order each sample adds I - phi(1) (x^2 - 1) (I: |x| > 1, unit sigma),
  // whose variance is p (1 - p) - 2 phi(1)^2: two thirds of the binomial spread.
  const double p = kGaussianShareAboveSigma;
  const double phi1 = std::exp(-0.5) / std::sqrt(2.0 * kPi);
  profile.gaussian_standard_error = std::sqrt((p * (1.0 - p) - 2.0 * phi1 * phi1) * sum_of_squared_weights) / p;
  // The squares once: every sample lies in about window / hop windows (80 by default).
  std::vector<float> squares(rir.size());
  for (std::size_t n = 0; n < rir.size(); ++n) squares[n] = rir[n] * rir[n];
  const std::vector<float> weights(w.begin(), w.end());
  // Only windows wholly inside the signal: zero padding would read as sparse.
  for (std::size_t centre = half; centre + half < rir.size(); centre += hop) {
    double mean_square = 0.0;
    const double share = detail::windowShareAboveSigma(squares.data() + (centre - half), weights.data(), length, mean_square);
    profile.time_s.push_back(static_cast<double>(centre) / fs);
    profile.density.push_back(share / kGaussianShareAboveSigma);
    profile.mean_square.push_back(mean_square);
  }
  return profile;
}

MixingTimeResult estimateMixingTime(const EchoDensityProfile& profile, double direct_sound_s,
                                    const MixingTimeOptions& options) {
  const std::size_t frames = profile.density.size();
  if (frames == 0) throw InputError("mixing time: the echo density profile is empty");
  if (!(options.threshold > 0.0)) throw InputError("mixing time: the threshold must be positive");
  if (!(options.standard_errors >= 0.0)) throw InputError("mixing time: standard_errors must not be negative");

  // Background noise from the last tenth of the profile.
  const std::size_t tail_first = frames - std::max<std::size_t>(1, frames / 10);
  double noise = 0.0;
  for (std::size_t i = tail_first; i < frames; ++i) noise += profile.mean_square[i];
  noise /= static_cast<double>(frames - tail_first);
  const double gate = noise * std::pow(10.0, options.noise_gate_db / 10.0);

  std::vector<std::size_t> candidates;  // frames after the direct sound, above the gate
  for (std::size_t i = 0; i < frames; ++i) {
    if (profile.time_s[i] >= direct_sound_s && profile.mean_square[i] > gate) candidates.push_back(i);
  }
  if (candidates.empty()) {
    throw InputError("mixing time: no analysis window after the direct sound rises " +
                     text(options.noise_gate_db) +
                     " dB above the background noise; check the direct-sound time and the RIR's level");
  }

  MixingTimeResult result;
  for (std::size_t i : candidates) result.peak_density = std::max(result.peak_density, profile.density[i]);

  auto crossing = [&](double level) -> double {
    for (std::size_t j = 0; j < candidates.size(); ++j) {
      const std::size_t i = candidates[j];
      if (profile.density[i] < level) continue;
      // Interpolate from the previous frame when it is the adjacent one.
      if (j > 0 && candidates[j - 1] + 1 == i) {
        const double d0 = profile.density[i - 1], d1 = profile.density[i];
        const double f = d1 > d0 ? (level - d0) / (d1 - d0) : 1.0;
        return profile.time_s[i - 1] + std::clamp(f, 0.0, 1.0) * (profile.time_s[i] - profile.time_s[i - 1]);
      }
      return profile.time_s[i];
    }
    return -1.0;
  };

  const double t = crossing(options.threshold - options.standard_errors * profile.gaussian_standard_error);
  if (t >= 0.0) {
    result.mixing_time_s = t;
    result.reached_threshold = true;
    return result;
  }
  result.mixing_time_s = crossing(options.fallback_fraction_of_peak * result.peak_density);
  result.note = "the echo density never reaches " + text(options.threshold) +
                " after the direct sound (peak " + text(result.peak_density) +
                "); the mixing time is where it first reaches " +
                text(options.fallback_fraction_of_peak) + " of that peak";
  return result;
}

}  // namespace room_reverb::core
