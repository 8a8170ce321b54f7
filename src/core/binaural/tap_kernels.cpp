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

// Sections section .. section + Sections - 1 of `Vectors` vectors of taps (lanes first ..
// first + Vectors * kTapLanes) over the block, in place on the sample-major `buffer`: the
// state stays in registers from sample to sample. A section's step is a chain of two
// dependent multiply-adds (latency-bound); the vectors' chains are independent, and so is
// the next section's step on this sample from this section's step on the next, so they
// overlap.
template <std::size_t Vectors, std::size_t Sections>
__attribute__((always_inline)) inline void sectionPass(const LaneSections& f, std::size_t section, std::size_t first,
                                                       float* __restrict buffer, std::size_t frames) {
  constexpr std::size_t kBytes = sizeof(Lanes);
  const std::size_t lanes = f.lanes;
  Lanes c0[Sections][Vectors], c1[Sections][Vectors], c2[Sections][Vectors], d1[Sections][Vectors],
      d2[Sections][Vectors], z1[Sections][Vectors], z2[Sections][Vectors];
  for (std::size_t s = 0; s < Sections; ++s) {
    for (std::size_t v = 0; v < Vectors; ++v) {
      const std::size_t i = (section + s) * lanes + first + v * kTapLanes;
      __builtin_memcpy(&c0[s][v], f.b0 + i, kBytes);
      __builtin_memcpy(&c1[s][v], f.b1 + i, kBytes);
      __builtin_memcpy(&c2[s][v], f.b2 + i, kBytes);
      __builtin_memcpy(&d1[s][v], f.a1 + i, kBytes);
      __builtin_memcpy(&d2[s][v], f.a2 + i, kBytes);
      __builtin_memcpy(&z1[s][v], f.s1 + i, kBytes);
      __builtin_memcpy(&z2[s][v], f.s2 + i, kBytes);
    }
  }
  for (std::size_t n = 0; n < frames; ++n) {
    float* at = buffer + n * lanes + first;
    for (std::size_t v = 0; v < Vectors; ++v) {
      Lanes y;
      __builtin_memcpy(&y, at + v * kTapLanes, kBytes);
      for (std::size_t s = 0; s < Sections; ++s) {
        const Lanes result = c0[s][v] * y + z1[s][v];
        z1[s][v] = c1[s][v] * y - d1[s][v] * result + z2[s][v];
        z2[s][v] = c2[s][v] * y - d2[s][v] * result;
        y = result;
      }
      __builtin_memcpy(at + v * kTapLanes, &y, kBytes);
    }
  }
  for (std::size_t s = 0; s < Sections; ++s) {
    for (std::size_t v = 0; v < Vectors; ++v) {
      const std::size_t i = (section + s) * lanes + first + v * kTapLanes;
      __builtin_memcpy(f.s1 + i, &z1[s][v], kBytes);
      __builtin_memcpy(f.s2 + i, &z2[s][v], kBytes);
    }
  }
}

// Every section for the vectors of taps first .. first + Vectors * kTapLanes, two to a pass.
template <std::size_t Vectors>
__attribute__((always_inline)) inline void allSections(const LaneSections& f, std::size_t first, float* buffer,
                                                       std::size_t frames) {
  std::size_t s = 0;
  for (; s + 2 <= f.sections; s += 2) sectionPass<Vectors, 2>(f, s, first, buffer, frames);
  if (s < f.sections) sectionPass<Vectors, 1>(f, s, first, buffer, frames);
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
  // their own chains. Two sections to a pass: the second's step on a sample overlaps the
  // first's on the next (24 taps, five sections: 15.5 us a block against 17.0 us one
  // section a pass, bench_binaural_renderer BM_MovingTapsBlock).
  std::size_t first = 0;
  for (; first + 4 * kTapLanes <= lanes; first += 4 * kTapLanes) allSections<4>(f, first, scratch, frames);
  switch ((lanes - first) / kTapLanes) {
    case 3: allSections<3>(f, first, scratch, frames); break;
    case 2: allSections<2>(f, first, scratch, frames); break;
    case 1: allSections<1>(f, first, scratch, frames); break;
    default: break;
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
