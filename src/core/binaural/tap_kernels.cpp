#include "tap_kernels.h"

#include "../common/simd_clones.h"

namespace room_reverb::core {

ROOM_REVERB_SIMD_CLONES
void interpolateCubic(const float* x, float t0, float dt, std::size_t count, float* __restrict out) {
  // A signed 32-bit counter and the four reads as their own pointers: an unsigned 64-bit
  // index converted to float, or x[n - 1] with n unsigned, keeps the loop scalar. The
  // fraction in single precision is within 10^-5 of a sample over a block of 256.
  const float* __restrict before = x - 1;
  const float* __restrict at = x;
  const float* __restrict next = x + 1;
  const float* __restrict after = x + 2;
  const int runs = static_cast<int>(count);
  for (int n = 0; n < runs; ++n) {
    const float t = t0 + static_cast<float>(n) * dt;
    const float tm1 = t - 1.0f, tm2 = t - 2.0f, tp1 = t + 1.0f;
    out[n] = -t * tm1 * tm2 * (1.0f / 6.0f) * before[n] + tp1 * tm1 * tm2 * 0.5f * at[n] -
             tp1 * t * tm2 * 0.5f * next[n] + tp1 * t * tm1 * (1.0f / 6.0f) * after[n];
  }
}

namespace {

// kTapLanes floats, one vector register with AVX (two SSE2 registers in the baseline
// clone): GCC's vector extension, so that the lanes are vectorised by construction. The
// arrays are only as aligned as floats are, so vectors move in and out by memcpy
// (unaligned loads and stores).
typedef float Lanes __attribute__((vector_size(kTapLanes * sizeof(float))));

}  // namespace

// One section of `Vectors` vectors of taps (lanes first .. first + Vectors * kTapLanes) over
// the block, in place on the sample-major `buffer`: the state stays in registers from
// sample to sample, and the vectors' recursions are independent, so they overlap (one
// tap's recursion alone is a chain of dependent multiply-adds, latency-bound).
template <std::size_t Vectors>
__attribute__((always_inline)) inline void sectionPass(const LaneSections& f, std::size_t section, std::size_t first, float* __restrict buffer,
                        std::size_t frames) {
  constexpr std::size_t kBytes = sizeof(Lanes);
  const std::size_t lanes = f.lanes;
  Lanes c0[Vectors], c1[Vectors], c2[Vectors], d1[Vectors], d2[Vectors], z1[Vectors], z2[Vectors];
  for (std::size_t v = 0; v < Vectors; ++v) {
    const std::size_t i = section * lanes + first + v * kTapLanes;
    __builtin_memcpy(&c0[v], f.b0 + i, kBytes);
    __builtin_memcpy(&c1[v], f.b1 + i, kBytes);
    __builtin_memcpy(&c2[v], f.b2 + i, kBytes);
    __builtin_memcpy(&d1[v], f.a1 + i, kBytes);
    __builtin_memcpy(&d2[v], f.a2 + i, kBytes);
    __builtin_memcpy(&z1[v], f.s1 + i, kBytes);
    __builtin_memcpy(&z2[v], f.s2 + i, kBytes);
  }
  for (std::size_t n = 0; n < frames; ++n) {
    float* at = buffer + n * lanes + first;
    for (std::size_t v = 0; v < Vectors; ++v) {
      Lanes y;
      __builtin_memcpy(&y, at + v * kTapLanes, kBytes);
      const Lanes result = c0[v] * y + z1[v];
      z1[v] = c1[v] * y - d1[v] * result + z2[v];
      z2[v] = c2[v] * y - d2[v] * result;
      __builtin_memcpy(at + v * kTapLanes, &result, kBytes);
    }
  }
  for (std::size_t v = 0; v < Vectors; ++v) {
    const std::size_t i = section * lanes + first + v * kTapLanes;
    __builtin_memcpy(f.s1 + i, &z1[v], kBytes);
    __builtin_memcpy(f.s2 + i, &z2[v], kBytes);
  }
}

// Section by section over the whole block (sectionPass), up to four vectors of taps at a
// time, on a sample-major copy of the taps' signals.
ROOM_REVERB_SIMD_CLONES
void runLaneSections(const LaneSections& f, float* samples, float* scratch, std::size_t frames) {
  const std::size_t lanes = f.lanes;
  // The transposes go a vector of taps at a time: its rows read in step, one vector
  // written per sample (a tap at a time strides through memory and took as long as the
  // filters).
  for (std::size_t k = 0; k < lanes; k += kTapLanes) {
    const float* __restrict rows = samples + k * frames;
    float* __restrict to = scratch + k;
    for (std::size_t n = 0; n < frames; ++n) {
      for (std::size_t j = 0; j < kTapLanes; ++j) to[n * lanes + j] = rows[j * frames + n];
    }
  }
  // Up to four vectors in one pass: a recursion's step is two dependent multiply-adds
  // (about 8 cycles), in which three or four vectors' updates fit, so the taps of a
  // typical RSAO (up to 32) run as one pass; two passes of fewer vectors each wait on
  // their own chains.
  for (std::size_t s = 0; s < f.sections; ++s) {
    std::size_t first = 0;
    for (; first + 4 * kTapLanes <= lanes; first += 4 * kTapLanes) sectionPass<4>(f, s, first, scratch, frames);
    switch ((lanes - first) / kTapLanes) {
      case 3: sectionPass<3>(f, s, first, scratch, frames); break;
      case 2: sectionPass<2>(f, s, first, scratch, frames); break;
      case 1: sectionPass<1>(f, s, first, scratch, frames); break;
      default: break;
    }
  }
  for (std::size_t k = 0; k < lanes; k += kTapLanes) {
    float* __restrict rows = samples + k * frames;
    const float* __restrict from = scratch + k;
    for (std::size_t n = 0; n < frames; ++n) {
      for (std::size_t j = 0; j < kTapLanes; ++j) rows[j * frames + n] = from[n * lanes + j];
    }
  }
}

// Channel by channel, a tile of samples summed over every tap in registers before it is
// added to the field: the field is read and written once per channel, not once per tap.
ROOM_REVERB_SIMD_CLONES
void encodeGliding(const float* __restrict signals, std::size_t taps, const float* __restrict from,
                   const float* __restrict change, std::size_t channels, const float* __restrict ramp,
                   float* const* field, std::size_t frames) {
  constexpr std::size_t kTile = 32;
  for (std::size_t c = 0; c < channels; ++c) {
    float* __restrict out = field[c];
    std::size_t n0 = 0;
    for (; n0 + kTile <= frames; n0 += kTile) {
      float sum[kTile] = {};
      for (std::size_t k = 0; k < taps; ++k) {
        const float g = from[k * channels + c], dg = change[k * channels + c];
        const float* __restrict x = signals + k * frames + n0;
        for (std::size_t j = 0; j < kTile; ++j) sum[j] += (g + dg * ramp[n0 + j]) * x[j];
      }
      for (std::size_t j = 0; j < kTile; ++j) out[n0 + j] += sum[j];
    }
    for (std::size_t n = n0; n < frames; ++n) {
      for (std::size_t k = 0; k < taps; ++k) {
        out[n] += (from[k * channels + c] + change[k * channels + c] * ramp[n]) * signals[k * frames + n];
      }
    }
  }
}

}  // namespace room_reverb::core
