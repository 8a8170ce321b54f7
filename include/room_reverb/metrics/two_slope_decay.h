#pragma once
// A bent energy decay as the sum of two exponentials, fitted to Schroeder's curve.
//
// Coupled volumes, rooms whose absorption sits on one pair of surfaces (a grazing field
// along the reflective ones outlives the rest) and bands whose first arrivals stand above
// the diffuse field decay fast first and slowly later: EDT < T20 < T30 on one curve. The
// model of such a decay is the sum of two exponential energy decays (Xiang & Goggans 2001,
// "Evaluation of decay times in coupled spaces"), whose backward integral is again a sum:
//
//   R(t) = A_1 exp(-a_1 t) + A_2 exp(-a_2 t),   a_1 > a_2 > 0,  A_1, A_2 >= 0,
//
// R(t) the energy remaining after t (EnergyDecay::energyAfter), a_i the energy decay rates
// (T60_i = 6 ln(10) / a_i). The fit minimises the squared relative error of R over the
// curve from its start down to end_db: for given rates the amplitudes are a 2 x 2 linear
// least-squares problem, and the rates are searched on a logarithmic grid, then refined
// from its best point by a simplex. The best single exponential over the same span is fitted the same way,
// so a caller can tell whether the curve is bent at all.
#include <cstddef>

#include "room_reverb/metrics/energy_decay.h"

namespace room_reverb::core {

struct TwoSlopeFit {
  bool valid = false;            // the curve reaches end_db and both fits converged
  double end_s = 0.0;            // the fitted span is [0, end_s], seconds from the curve's start
  // The two-exponential model (A_i in the units of EnergyDecay::energyAfter).
  double fast_rate_per_s = 0.0;  // a_1
  double slow_rate_per_s = 0.0;  // a_2
  double fast_energy = 0.0;      // A_1
  double slow_energy = 0.0;      // A_2
  double rms_error_db = 0.0;     // its RMS level error over the span
  // The best single exponential R(t) = A exp(-a t) over the same span.
  double one_rate_per_s = 0.0;
  double one_energy = 0.0;
  double one_rms_error_db = 0.0;
  // Where the two terms of R are equal (seconds; negative or past end_s when one term
  // dominates the whole span).
  double crossover_s() const;
};

// Fits both models to `decay` from its start (0 dB) down to `end_db` (< 0), reading the
// curve at most `max_points` times, evenly spaced in time. Invalid when the curve is
// invalid or does not fall to end_db before Lundeby's crosspoint (past it the curve is
// the extrapolated decay line, not a measurement).
TwoSlopeFit fitTwoSlopes(const EnergyDecay& decay, double end_db, std::size_t max_points = 96);

}  // namespace room_reverb::core
