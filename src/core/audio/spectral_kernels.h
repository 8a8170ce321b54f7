#pragma once
// The convolver's inner loops over split complex spectra ("rows": `stride` real parts, then
// `stride` imaginary parts, stride a multiple of kRowAlignmentFloats so every row starts on
// a cache line and the loops run over whole SIMD vectors).
#include <complex>
#include <cstddef>

namespace room_reverb::core {

constexpr std::size_t kRowAlignmentFloats = 16;

// Floats of one row's real (or imaginary) half for `bins` bins.
constexpr std::size_t rowStride(std::size_t bins) {
  return (bins + kRowAlignmentFloats - 1) / kRowAlignmentFloats * kRowAlignmentFloats;
}

// y += x * h over the first n bins.
void multiplyAccumulate(const float* x, const float* h, float* y, std::size_t stride, std::size_t n);
// y += x0 * h0 + x1 * h1: two partitions per pass over the accumulator.
void multiplyAccumulatePair(const float* x0, const float* h0, const float* x1, const float* h1, float* y,
                            std::size_t stride, std::size_t n);

// Interleaved spectrum (as RealFft gives it) <-> row.
void splitSpectrum(const std::complex<float>* spectrum, std::size_t bins, float* row, std::size_t stride);
void joinSpectrum(const float* row, std::size_t stride, std::size_t bins, std::complex<float>* spectrum);

}  // namespace room_reverb::core
