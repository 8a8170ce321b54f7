#pragma once
// Streaming multichannel FIR convolution for the real-time renderer: uniformly partitioned
// overlap-save with a frequency-domain delay line (UPOLS / FDL).
//
// Each input block of B frames is transformed once (FFT of 2B: the previous block and this
// one) into the delay line. Every filter is cut into partitions of B taps, each transformed
// once when the filters are set; the output spectrum of a block is the sum over partitions
// p and inputs i of (spectrum of input block k-p) x (partition p of filter i->o), and its
// inverse FFT's second half is the output block. Work per block: one forward FFT per input,
// one inverse FFT per output and inputs x outputs x partitions complex multiply-adds of
// B+1 bins, which dominate for long filters: every block streams all filter spectra
// (8 bytes per tap and filter) and the delay line from memory, so the cost per second of
// audio grows with filter length / B. Long filters at small blocks are memory-bound (2 s
// 16 x 2 filters at B = 256 move about 37 MB per 5.3 ms block); they call for larger
// blocks or a non-uniform partitioning built from several of these convolvers.
//
// Timing ("latency is exactly one block"). process() adds no delay: frame j of the block
// returned by the k-th call (k = 0, 1, ...) is y[kB + j], where y = x * h is the linear
// convolution of the whole input stream so far, so an impulse at stream frame n appears as
// h starting at output stream frame n. What remains is the one block of buffering any block
// processor has: in a duplex sound-card loop the block captured during period k is
// processed at its end and played during period k+1, so every input sample leaves exactly
// B frames after it entered (not counting driver and converter latency).
//
// Filter swap. setFilters() transforms the new matrix (it allocates, so call it outside the
// audio callback or accept the cost there) and the swap starts with the next process()
// call: over `crossfade_blocks` blocks both matrices run on the same delay line and their
// outputs are mixed with raised-cosine gains that sum to one (an equal-gain fade: the two
// outputs are convolutions of one input and strongly correlated, so an equal-power fade
// would swell by up to 3 dB). Because the delay line holds the input history, not the
// output, the old filter's tail keeps ringing through the fade and the new filter starts
// with its full tail: there is no gap and no click. A swap asked for during a fade waits
// for that fade to end (only the latest such request is kept). A block inside a fade costs
// twice the multiply-adds.
//
// process() allocates nothing and frees nothing. Not thread-safe: call setFilters() and
// process() from one thread, or under the caller's lock.
#include <cstddef>
#include <memory>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/fft.h"

namespace room_reverb::core {

// filters[i][o]: the FIR from input channel i to output channel o. Filters of one matrix
// may differ in length; each needs at least one tap (a single 0 for "no path").
using FilterMatrix = std::vector<std::vector<std::vector<float>>>;

class PartitionedConvolver {
 public:
  static constexpr std::size_t kDefaultBlockSize = 256;

  // Throws InputError for a block size or crossfade length of zero, a matrix with no
  // inputs or outputs, rows with different output counts, empty filters or non-finite taps.
  explicit PartitionedConvolver(const FilterMatrix& filters,
                                std::size_t block_size = kDefaultBlockSize,
                                std::size_t crossfade_blocks = 1);
  ~PartitionedConvolver();
  PartitionedConvolver(const PartitionedConvolver&) = delete;
  PartitionedConvolver& operator=(const PartitionedConvolver&) = delete;

  std::size_t inputCount() const { return input_count_; }
  std::size_t outputCount() const { return output_count_; }
  std::size_t blockSize() const { return block_size_; }
  std::size_t crossfadeBlocks() const { return crossfade_blocks_; }
  // Partitions of the longest filter currently in use.
  std::size_t partitionCount() const;
  bool crossfading() const { return fade_block_ < crossfade_blocks_; }

  // Replaces the matrix, with the crossfade described above. The new matrix must have the
  // same numbers of inputs and outputs (InputError otherwise); its filters may be longer or
  // shorter. A longer filter than any before grows the delay line, keeping its history.
  void setFilters(const FilterMatrix& filters);

  // One block: `input` has inputCount() channels of exactly blockSize() frames (InputError
  // otherwise). `output` is reshaped to outputCount() x blockSize() if it is not already
  // (so reusing one output buffer allocates only on the first call); its sample rate is
  // copied from the input.
  void process(const AudioBuffer& input, AudioBuffer& output);
  // The same without checks, for audio callbacks: inputs[i] and outputs[o] each point to
  // blockSize() samples. Inputs and outputs must not overlap.
  void process(const float* const* inputs, float* const* outputs);

  // Forgets the input history (as if silence had been playing forever) and completes any
  // fade at once, e.g. after a dropout or when a new stream starts.
  void reset();

 private:
  struct FilterSpectra;

  std::unique_ptr<FilterSpectra> transform(const FilterMatrix& filters);
  void growDelayLine(std::size_t partitions);
  void startPendingFade();
  void pushInputs(const float* const* inputs);
  void render(const FilterSpectra& spectra, float* const* outputs);

  std::size_t input_count_;
  std::size_t output_count_;
  std::size_t block_size_;
  std::size_t crossfade_blocks_;
  std::size_t bins_;    // B + 1 bins of a 2B real FFT
  std::size_t stride_;  // bins_ rounded up so every spectrum row starts vector-aligned

  RealFft fft_;
  // Filter sets: the one in use, the one fading out (kept allocated after the fade so
  // process() never frees), and a swap waiting for the current fade to end.
  std::unique_ptr<FilterSpectra> current_;
  std::unique_ptr<FilterSpectra> previous_;
  std::unique_ptr<FilterSpectra> pending_;
  bool swap_waiting_ = false;          // pending_ holds a set to fade to
  std::size_t fade_block_;             // blocks of the fade done; == crossfade_blocks_ when idle
  std::vector<float> fade_in_gain_;    // per fade sample, the new set's gain

  // Delay line: `capacity_` slots (a ring, newest at `newest_slot_`), each holding one
  // spectrum per input as split real and imaginary rows of stride_ floats.
  std::size_t capacity_;
  std::size_t newest_slot_;
  std::vector<float> delay_line_;

  // Scratch, preallocated.
  std::vector<float> input_windows_;             // per input, the last 2B input frames
  std::vector<float> accumulators_;              // per output, split spectrum
  std::vector<std::complex<float>> spectrum_;    // bins_, for the FFT
  std::vector<float> time_;                      // 2B, for the FFT
  std::vector<float> fade_out_samples_;          // outputs x B, the old set's output
  std::vector<float*> fade_out_pointers_;
  std::vector<const float*> input_pointers_;    // for the AudioBuffer overload of process()
  std::vector<float*> output_pointers_;
};

}  // namespace room_reverb::core
