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

// Filter partitions times delay-line spectra, summed, for up to kOutputGroup outputs of
// one input at once: y[o] += sum over q < partitions of x(q) h[o] + q h_step, for
// o < outputs, over every bin of the rows. x(q) is the delay line's row q blocks older than
// its newest: slot (newest - q) mod slots of `slots` rows `slot_step` floats apart from
// `ring`. Each delay-line spectrum is loaded once for the whole group and each
// accumulator once per four partitions, so the loop is bound by the multiply-adds rather
// than by loads (one output at a time it loads two floats per multiply-add).
constexpr std::size_t kOutputGroup = 4;
struct DelayLineRows {
  const float* ring;
  std::size_t slots;
  std::size_t slot_step;
  std::size_t newest;
};
void multiplyAccumulateOutputs(const DelayLineRows& x, std::size_t partitions, const float* const* h,
                               std::size_t h_step, std::size_t outputs, float* const* y, std::size_t stride);

// Interleaved spectrum (as RealFft gives it) <-> row.
void splitSpectrum(const std::complex<float>* spectrum, std::size_t bins, float* row, std::size_t stride);
void joinSpectrum(const float* row, std::size_t stride, std::size_t bins, std::complex<float>* spectrum);

}  // namespace room_reverb::core
