#pragma once
// Linear prediction of a reflection's spectral shape (RSAO, Remaggi et al. section 2.1:
// each early reflection carries an all-pole filter fitted to its windowed W segment),
// and the same filter as a cascade of second-order sections for stable resynthesis.
#include <vector>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

// The paper's prediction order.
constexpr int kDefaultLpcOrder = 9;

// An all-pole model gain / A(z), A(z) = 1 + sum_{i=1..p} a[i] z^-i.
struct LpcModel {
  std::vector<double> a;                       // a[0] == 1, size order + 1
  double gain = 0.0;                           // sqrt of the final prediction-error energy
  std::vector<double> reflection_coefficients;  // k_1..k_p of the lattice, |k| < 1 when stable
};

// Biased autocorrelation r[0..max_lag] (sum over the whole segment, not divided by its
// length): the "autocorrelation method", whose normal equations are Toeplitz and whose
// solution is always minimum phase.
std::vector<double> autocorrelation(const std::vector<double>& x, int max_lag);

// r[0..max_lag] of a signal whose power spectrum is x's above cutoff_rad (radians per
// sample) and x's value at cutoff_rad below it, scaled so that r[0] stays x's energy (the
// gain matching of levinsonDurbin holds: only the shape changes). Computed from |X|^2
// sampled at a power of two of points, at least 2 |x| and 8 per cutoff, so that the result
// stays a valid autocorrelation and levinsonDurbin of it minimum phase. A cutoff of 0 (or
// below) gives autocorrelation(x, max_lag).
std::vector<double> autocorrelationFlatBelow(const std::vector<double>& x, int max_lag, double cutoff_rad);

// Levinson-Durbin recursion on r[0..order]. With r unnormalised, gain^2 = r[0] prod(1 - k_i^2)
// is the residual energy, so the impulse response of gain / A(z) has the energy r[0] of
// the segment (Makhoul 1975, gain matching). An all-zero r gives A = 1, gain 0. If the
// error vanishes before `order` (a perfectly predictable segment) the recursion stops and
// the remaining coefficients are zero. InputError for order < 1, r shorter than order + 1,
// r[0] < 0 or non-finite values.
LpcModel levinsonDurbin(const std::vector<double>& r, int order);

// autocorrelation + levinsonDurbin: the LPC fit of one (already windowed) segment.
LpcModel fitLpc(const std::vector<double>& segment, int order = kDefaultLpcOrder);

// gain / A(z) as cascaded sections: the roots of A (eigenvalues of its companion matrix,
// from Eigen's real Schur form) are grouped into conjugate pairs (one biquad each), real
// roots two by two, and a single real root left over for odd order makes a first-order
// section (b2 = a2 = 0). The gain sits in the first section's b0. InputError unless
// a[0] == 1.
std::vector<BiquadSection> allPoleToSections(const std::vector<double>& a, double gain);

// y = cascade(x), each section in transposed direct form II, zero initial state.
std::vector<double> filterSections(const std::vector<BiquadSection>& sections, const std::vector<double>& x);

// y[n] = gain x[n] - sum_{i>=1} a[i] y[n-i]: the direct-form all-pole filter (the
// reference the sections are checked against; numerically fragile for high orders).
std::vector<double> filterAllPole(const std::vector<double>& a, double gain, const std::vector<double>& x);

}  // namespace room_reverb::core
