#pragma once
// The amplitude envelope of one late-reverb band: the model the estimator fits and the
// resynthesis and renderers play. With t_0 = LateReverb::onset_s, t_m = mixing_time_s,
// u = (t - t_0) / (t_m - t_0):
//
//   e_b(t) = 0                                           t < t_0
//          = level_b * ramp(u)                           t_0 <= t < t_m, onset_level_b = 0
//          = onset_level_b * (level_b / onset_level_b)^u t_0 <= t < t_m, onset_level_b > 0
//          = level_b * d_b(t - t_m)                      t >= t_m
//
// d_b(t') = exp(-delta_b t') for one slope, the paper's decay; for a bent band
// (LateReverbBand::second_share w > 0) d_b(t')^2 = (1 - w) exp(-2 delta_1 t') + w exp(-2 delta_2 t').
//
// The first form is the paper's (and VISR's) onset ramp, linear or raised-cosine, from zero
// at the first reflection to the band's level at the mixing time. The second is this
// project's extension for rooms whose early energy the discrete reflections do not hold
// (onset_ramp_fit.h): an exponential course from the onset level to the mixing-time level,
// the faster early decay that makes a measured EDT shorter than its T20. After the mixing
// time both are the measured decay.
#include <cstddef>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

enum class OnsetRamp { kLinear, kRaisedCosine };

// Whether the band's decay has two slopes (LateReverbBand::second_share > 0).
bool hasTwoSlopes(const LateReverbBand& band);

// One slope (second_share 0), or two with second_share in (0, 1) and both decay constants
// finite and positive: what every reader of an RSAO (file, message, renderer) requires.
bool slopesWellFormed(const LateReverbBand& band);

// d_b(t'): the band's decay after the mixing time, 1 at t' = 0.
double lateDecayGain(const LateReverbBand& band, double since_mixing_s);

// The time after the mixing time [s] by which d_b has fallen by `drop_db` (its T60 for one
// slope and 60 dB).
double lateDecayLengthS(const LateReverbBand& band, double drop_db = 60.0);

// e_b(t) / level_b for band `band` of `late`, t from the first sample of the RIR (0 when
// level_b is 0).
double lateEnvelopeGain(const LateReverb& late, std::size_t band, double t, OnsetRamp shape = OnsetRamp::kLinear);

// sum over samples n in [from, to) of e_b(n / fs)^2 with the linear ramp: the energy of
// unit-mean-square noise under the envelope. The exponential parts (the extended course,
// each slope of the decay) are geometric series, summed in closed form; the ramp sample by sample.
double lateEnvelopeEnergy(const LateReverb& late, std::size_t band, std::size_t from, std::size_t to, double fs);

}  // namespace room_reverb::core
