#pragma once
// The reflection taps' inner loops (reflection_tap_bank.h), each over a whole block so that
// it vectorises: the taps' reads of the delay line, their filters run side by side (one tap
// per SIMD lane: a tap's recursion is serial in time, but the taps are independent), and
// their encoding into the field.
#include <cstddef>

namespace room_reverb::core {

// Taps run side by side in vectors of this many lanes, in single precision as the field
// is (eight to an AVX register: twice the taps per instruction of double precision).
constexpr std::size_t kTapLanes = 8;

// Filter coefficients per section, each for `lanes` taps side by side (a multiple of
// kTapLanes): the section s of tap k is b0[s * lanes + k] ... a2[s * lanes + k]; its
// transposed direct form II state is s1, s2 at the same place.
struct LaneSections {
  const float* b0;
  const float* b1;
  const float* b2;
  const float* a1;
  const float* a2;
  float* s1;
  float* s2;
  std::size_t sections;
  std::size_t lanes;
};

// Cubic Lagrange interpolation of x at fractional positions t0 + n * dt past x[n]
// (n = 0 .. count - 1), each t within [0, 1] up to rounding: out[n] = sum over
// i = -1 .. 2 of x[n + i] L_i(t). x[-1] and x[count + 1] must be readable.
void interpolateCubic(const float* x, float t0, float dt, std::size_t count, float* out);

// Runs every lane's cascade over `frames` samples, in place: samples[k * frames + n] is
// tap k's sample n. scratch holds frames * lanes floats.
void runLaneSections(const LaneSections& filters, float* samples, float* scratch, std::size_t frames);

// field[c][n] += sum over taps k of (from[k * channels + c] + change[k * channels + c]
// ramp[n]) signals[k * frames + n], for c < channels, n < frames: each tap encoded with
// gains gliding across the block (and the stream's head rotation, one ambisonic order's
// channels at a time, binaural_stream.cpp).
void encodeGliding(const float* signals, std::size_t taps, const float* from, const float* change,
                   std::size_t channels, const float* ramp, float* const* field, std::size_t frames);

}  // namespace room_reverb::core
