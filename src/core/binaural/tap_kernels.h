#pragma once
// The reflection taps' inner loops (reflection_tap_bank.h), each over a whole block so that
// it vectorises: the taps' reads of the delay line, their filters run side by side (one tap
// per SIMD lane: a tap's recursion is serial in time, but the taps are independent), and
// their encoding into the field.
#include <cstddef>

namespace room_reverb::core {

// Taps run side by side in vectors of this many lanes.
constexpr std::size_t kTapLanes = 4;

// Filter coefficients per section, each for `lanes` taps side by side (a multiple of
// kTapLanes): the section s of tap k is b0[s * lanes + k] ... a2[s * lanes + k]; its
// transposed direct form II state is s1, s2 at the same place.
struct LaneSections {
  const double* b0;
  const double* b1;
  const double* b2;
  const double* a1;
  const double* a2;
  double* s1;
  double* s2;
  std::size_t sections;
  std::size_t lanes;
};

// Cubic Lagrange interpolation of x at fractional positions t0 + n * dt past x[n]
// (n = 0 .. count - 1), each t within [0, 1] up to rounding: out[n] = sum over
// i = -1 .. 2 of x[n + i] L_i(t). x[-1] and x[count + 1] must be readable.
void interpolateCubic(const float* x, double t0, double dt, std::size_t count, double* out);

// Runs every lane's cascade over `frames` samples, in place: samples[k * frames + n] is
// tap k's sample n. scratch holds frames * lanes doubles.
void runLaneSections(const LaneSections& filters, double* samples, double* scratch, std::size_t frames);

// field[c][n] += sum over taps k of (from[k * channels + c] + change[k * channels + c]
// ramp[n]) signals[k * frames + n], for c < channels, n < frames: each tap encoded with
// gains gliding across the block.
void encodeGliding(const float* signals, std::size_t taps, const float* from, const float* change,
                   std::size_t channels, const float* ramp, float* const* field, std::size_t frames);

}  // namespace room_reverb::core
