#pragma once
// Late-reverberation part of the RSAO estimator (Remaggi et al., section 2.1; Coleman et
// al., S3A object-based reverb): per octave band of the W channel, an exponential decay
// fitted to the Schroeder curve after the mixing time, the level there, and the onset ramp
// from the first reflection to the mixing time, each band with a reliability verdict.
//
// Per band b (the S3A renderer's nine octaves, 63 Hz .. 16 kHz, BandFilterBank):
//   - Schroeder's backward-integrated energy from the mixing time on, with the noise floor
//     found by Lundeby's method, its power subtracted and the energy lost past the
//     truncation point added back (EnergyDecay, metrics module);
//   - a least-squares line through that curve between fit_start_db and fit_end_db (the
//     paper: the first 20 dB), slope s_b in dB/s, intercept I_b in dB at the mixing time;
//   - decay constant delta_b = -s_b ln(10) / 20 (amplitude envelope exp(-delta_b t), energy
//     exp(-2 delta_b t)), T60_b = -60 / s_b = 3 ln(10) / delta_b;
//   - level, defined so that a resynthesis reproduces it exactly:
//
//         level_b = sqrt(2 delta_b E_b),
//
//     E_b the band's (noise-compensated) energy remaining after the mixing time as the
//     fitted line gives it, integral of h_b^2 dt from t_mix to infinity, in s * full scale^2.
//     level_b is the RMS amplitude at the mixing time of the band's exponential envelope:
//     unit-mean-square band noise under level_b exp(-delta_b (t - t_mix)) has exactly that
//     remaining energy. Unlike the RMS of a short window at t_mix it does not scatter with
//     the noise-like fine structure of one RIR (a 20 ms window holds barely one period of
//     the 63 Hz band).
//
// Reliability (LateReverbBand::reliable / reason), first failing check wins:
//   - clipped input: a run of clip_run_samples or more equal full-peak samples at or after
//     the first reflection (clipping of the direct sound alone does not touch the tail);
//   - noise-dominated: Lundeby finds no decay, or the band rises less than
//     noise_dominated_below_db above its noise floor;
//   - too little decay range: less than |fit_end_db| + noise_margin_db above the noise;
//   - implausible T60: outside [min_plausible_t60_s, max_plausible_t60_s]. (The published
//     estimator reports 15-45 s decays in bands that hold only noise; here such a band is
//     flagged, never passed on as a measurement.)
// A band keeps its measured decay when one was measured and is plausible, even if it is
// flagged for its range; otherwise its decay is a substitute (interpolated on log frequency
// between the nearest bands with a measured plausible decay, or fallback_t60_s when there
// are none) and its level the RMS of the substitute_level_window_s after the mixing time.
// The reason says which. Substitutes keep a renderer sane; they are not measurements.
#include <vector>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

struct LateReverbOptions {
  double fit_start_db = 0.0;    // Schroeder levels re the energy remaining at the mixing time
  double fit_end_db = -20.0;    // the paper: the first 20 dB
  double noise_margin_db = 10.0;            // fit end this far above the noise (ISO 3382-1 asks 10 dB)
  double noise_dominated_below_db = 10.0;   // decay range under this: noise-dominated
  double min_plausible_t60_s = 0.05;
  double max_plausible_t60_s = 20.0;        // beyond the longest reverberation of real halls and churches
  double fallback_t60_s = 0.5;              // substitute when no band has a measured decay
  double substitute_level_window_s = 0.050;
  int clip_run_samples = 3;
  // This project's extension (LateReverbBand::second_share, metrics/two_slope_decay.h): a
  // reliable band whose Schroeder curve is bent gets two slopes, fitted from the mixing
  // time down to two_slope_depth_db (less where the noise is nearer: noise_margin_db above
  // it). Bent: the curve falls at least min_two_slope_depth_db there, one exponential misses
  // it by min_bend_db RMS or more, two by at most max_two_slope_error_ratio of that, and each
  // slope holds min_slope_share of the remaining energy. false: one slope, the paper's.
  bool two_slopes = true;
  double two_slope_depth_db = 40.0;
  double min_two_slope_depth_db = 25.0;
  double min_bend_db = 0.25;
  double max_two_slope_error_ratio = 0.6;
  double min_slope_share = 0.02;
};

// `w_channel_48k`: the omnidirectional (W) channel of the RIR at 48 kHz, time zero at its
// first sample. `first_reflection_s` is where the onset ramp starts, `mixing_time_s` where
// the decay is analysed from (both from the first sample). Returns the nine octave bands
// 63 Hz .. 16 kHz. Throws InputError for an empty or non-finite signal, times out of order
// or negative, or less than 0.1 s of signal after the mixing time.
LateReverb estimateLateReverb(const std::vector<float>& w_channel_48k, double first_reflection_s,
                              double mixing_time_s, const LateReverbOptions& options = {});

}  // namespace room_reverb::core
