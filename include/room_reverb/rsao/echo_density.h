#pragma once
// Normalised echo density profile and the mixing time it implies (Abel & Huang, "A simple,
// robust measure of reverberation echo density", AES 121st Convention, 2006).
//
// In a sliding window the profile counts the (weighted) share of samples whose magnitude
// exceeds the window's standard deviation, and divides it by the share Gaussian noise would
// have, erfc(1/sqrt 2) = 0.3173:
//
//   eta(t) = 1/erfc(1/sqrt 2) * sum_tau w(tau) 1{|h(t + tau)| > sigma(t)},
//   sigma(t)^2 = sum_tau w(tau) h(t + tau)^2,   sum_tau w(tau) = 1.
//
// Sparse early reflections give eta << 1 (a few large samples hold the window's energy);
// once reflections overlap into a Gaussian-like diffuse tail, eta reaches 1. The first time
// it does after the direct sound is taken as the mixing time (RSAO, Remaggi et al., 2.1).
#include <cstddef>
#include <string>
#include <vector>

namespace room_reverb::core {

enum class EchoDensityWindow {
  // Default. A Hann weighting lets a strong reflection fade in and out of the window
  // instead of entering and leaving it at full weight, so the profile varies smoothly and
  // its first crossing of the threshold is not triggered by a window edge.
  kHann,
  // Uniform weights: a plain running count.
  kRectangular,
};

struct EchoDensityOptions {
  double window_s = 0.020;  // Abel & Huang: 20 ms
  EchoDensityWindow window = EchoDensityWindow::kHann;
  double hop_s = 0.00025;   // profile resolution; the mixing time is interpolated between frames
};

struct EchoDensityProfile {
  double sample_rate_hz = 0.0;
  std::vector<double> time_s;   // centre of each window, from the first sample of the RIR
  std::vector<double> density;  // eta at that time (0 where the window is silent)
  std::vector<double> mean_square;  // sigma^2 of the window: lets callers skip noise-only windows
  // Standard deviation of eta for Gaussian noise with this window (to first order in the
  // window's own sigma): sqrt((p (1 - p) - 2 phi(1)^2) sum w^2) / p, p = erfc(1/sqrt 2),
  // phi the normal density. About 0.039 for a 20 ms Hann window at 48 kHz.
  double gaussian_standard_error = 0.0;
};

// Throws InputError for a signal shorter than one window, a non-finite sample, or options
// out of range (window < 1 ms or > 1 s, hop <= 0 or longer than the window).
EchoDensityProfile echoDensityProfile(const std::vector<float>& rir, double sample_rate_hz,
                                      const EchoDensityOptions& options = {});

struct MixingTimeOptions {
  double threshold = 1.0;  // eta that counts as diffuse (the paper: 1)
  // A diffuse tail does not sit above 1: it scatters around it (and a decaying one a little
  // below it), so a literal 1.0 is met only once a fluctuation happens to push the profile
  // over, often tens of ms late. The profile counts as having reached the threshold once it
  // is within this many of its Gaussian-noise standard errors of it (0: the literal rule).
  // With two (eta >= 0.92 for a 20 ms Hann window) the estimate on synthetic tails lags the
  // true transition by 3.5-6 ms, a quarter of the window, over many noise draws.
  double standard_errors = 2.0;
  // Windows whose mean square is less than this far above the background noise (the mean
  // of the windows' mean squares over the last 10 % of the profile) are skipped: a window
  // holding only measurement noise, e.g. in a gap between the direct sound and the first
  // reflection, reads eta = 1 too, but is not a diffuse field.
  double noise_gate_db = 10.0;
  // Fallback when the profile never reaches the threshold: the first time (after the direct
  // sound, above the noise gate) it reaches this fraction of its highest value there.
  double fallback_fraction_of_peak = 0.95;
};

struct MixingTimeResult {
  double mixing_time_s = 0.0;     // from the first sample of the RIR
  bool reached_threshold = false; // false: mixing_time_s is the fallback
  double peak_density = 0.0;      // highest eta after the direct sound, above the noise gate
  std::string note;               // why the fallback was used ("" when reached_threshold)
};

// The first time at or after `direct_sound_s` the profile reaches the threshold (less the
// tolerance of MixingTimeOptions::standard_errors), linearly interpolated between the two
// frames around the crossing. The time is a window centre: it lags the start of the
// diffuse tail by about a quarter window. Throws InputError when no frame lies after the
// direct sound above the noise gate (nothing to judge).
MixingTimeResult estimateMixingTime(const EchoDensityProfile& profile, double direct_sound_s,
                                    const MixingTimeOptions& options = {});

}  // namespace room_reverb::core
