#pragma once
// Early arrivals of a first-order B-format RIR by matching pursuit against copies of the
// direct sound (this project's detector; the paper's group-delay onsets are
// group_delay_onsets.h). Every reflection of a wall is, to first order, a delayed, scaled
// and (by absorbing walls) low-passed copy of the direct sound, arriving as a plane wave:
// W = a s(t - t_k), (X, Y, Z) = u_k W. So:
//
//   1. the atoms are the direct sound cut from W (a short tapered window around it) and
//      copies of it low-passed by 1 and 2 one-pole sections at a few cut-offs (the
//      smeared onset of a dull wall's reflection), each scaled to unit energy; each has a
//      directional shape beside it, the direct sound's (X, Y, Z) along its own direction
//      cut and low-passed alike, so a microphone whose directional channels respond
//      otherwise than W is matched in them too;
//   2. the strongest correlation of any atom with the W residual over the early part
//      gives the next arrival: its time (parabolic peak, a fraction of a sample), its
//      atom; projecting W on the atom and X, Y, Z on its directional shape, both shifted
//      to that fraction, gives W's amplitude and the direction (X, Y, Z) / W (the
//      directional gain measured on the direct sound divided out);
//   3. the arrival is subtracted from all four channels, each with its own shape (the
//      direct sound first, so its tail does not hide the reflections riding on it), and
//      the search goes on.
//
// An arrival whose correlation does not stand min_detection_snr_db above the residual's
// local power (the matched filter's output for noise of that power) is not reported; the
// search ends when the strongest correlation left is below relative_threshold_db of the
// direct sound's. Close arrivals are parted because each is taken out before the next is
// sought, and each direction comes from the arrival's own projection, not from a window
// shared with its neighbours.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

struct MatchedArrivalOptions {
  // The direct sound's atom: W from this long before the direct sound's time to this long
  // after it, under a Tukey taper over its outer thirds. Short, so that a reflection
  // 0.3 ms after the direct sound is not part of the atom.
  double template_before_s = 0.00025;
  double template_after_s = 0.00025;
  // Cut-offs of the one-pole low-passes applied once and twice to the direct sound's atom.
  std::vector<double> low_pass_cutoffs_hz = {6000.0, 3000.0, 1500.0};
  int max_low_pass_passes = 2;
  // Matched-filter peak power over the residual's power per sample within +-noise_span_s
  // of the arrival (after its subtraction; from the median, matched_arrivals.cpp). For
  // Gaussian noise the largest of ~10^5 matched-filter outputs (atoms x lags of an 80 ms
  // early part) stands about 14 dB above its power; on the development rooms
  // (test_rsao_reflection_recall) recall is flat from 15 to 21 dB and falls from 24 dB.
  double min_detection_snr_db = 18.0;
  double noise_span_s = 0.002;
  // The arrival's matched energy over W's residual energy under its atom (weighted by the
  // atom's envelope) before it is taken out: an isolated pulse gives 1 or more, what a
  // mismatched atom leaves of a strong arrival far less.
  double min_explained_share = 0.5;
  // Arrivals closer than this to one already found are not sought (two band-limited
  // pulses closer than a few samples are one arrival at this bandwidth). At 0.2 ms the
  // pursuit leaves a first-order reflection 0.18 ms from another in the synthetic rooms of
  // reflection_rooms.h in its window, so that tap's spectrum carries it and a moved
  // listener hears the two together (docs/six_dof.md).
  double min_separation_s = 0.0001;
  // Nothing within this of the direct sound is sought: it is the loudspeaker's own
  // response (5 cm of path at 0.14 ms), which the direct sound's level and spectrum keep.
  // Parted from the direct sound at 0.14 ms, it shortens the resynthesis of the Tyndall
  // Bruce monument's 4 kHz T20 from -1.9 to -16.7 %.
  double direct_guard_s = 0.0002;
  // The search ends when the strongest correlation left is this far below the direct
  // sound's (in amplitude, dB).
  double relative_threshold_db = -30.0;
  std::size_t max_iterations = 400;
};

struct MatchedArrival {
  double time_s = 0.0;      // from the first sample, sub-sample resolution
  double amplitude = 0.0;   // W's projection on the unit-energy atom (signed)
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit, towards the source of the arrival
  // How much the four projections look like one plane wave, 0..1: 2 |a_W| |a_XYZ| /
  // (a_W^2 + |a_XYZ|^2) in SN3D, the window directness of direction_of_arrival.h applied
  // to the arrival's own coefficients.
  double directness = 0.0;
  double snr_db = 0.0;      // matched-filter peak power over the local residual power
  std::size_t atom = 0;     // 0: the direct sound's own shape; more: low-passed copies
  // The arrival in W as the pursuit took it out (its amplitude times its shifted atom),
  // sample w_first + i of the RIR at w_model[i].
  std::vector<double> w_model;
  std::size_t w_first = 0;
};

// The pursuit's arrivals and what it leaves of W: the RIR's W less every arrival's
// w_model, sample residual_first + i at w_residual[i] (the span the pursuit searched).
// An arrival alone is w_residual plus its own w_model: its neighbours taken out, the rest
// (the diffuse part, what no atom explains of its own shape) kept.
struct MatchedPursuit {
  std::vector<MatchedArrival> arrivals;
  std::vector<double> w_residual;
  std::size_t residual_first = 0;
};

// result[0] is the direct sound at direct_time_s; the rest are arrivals after it up to
// end_s, by time. InputError for fewer than 4 channels or bad options.
std::vector<MatchedArrival> matchedPursuitArrivals(const AudioBuffer& ambix_first_order, double direct_time_s,
                                                   double end_s, const MatchedArrivalOptions& options = {});
// The same, with W's residual.
MatchedPursuit matchedPursuit(const AudioBuffer& ambix_first_order, double direct_time_s, double end_s,
                              const MatchedArrivalOptions& options = {});

// InputError naming the bad field unless the options are usable.
void validateMatchedArrivalOptions(const MatchedArrivalOptions& options);

}  // namespace room_reverb::core
