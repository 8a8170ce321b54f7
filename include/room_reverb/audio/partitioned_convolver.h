#pragma once
// Streaming multichannel FIR convolution for the real-time renderer: non-uniformly
// partitioned overlap-save (NUPOLS; Gardner 1995, "Efficient convolution without
// input-output delay"; Garcia 2002; Wefers 2015, "Partitioned convolution algorithms for
// real-time auralization").
//
// The filters' first taps are cut into partitions of the block size B, later taps into
// partitions of 2B, 4B, ... up to `max_partition_size` (partition_plan.h chooses the
// sizes by a cost model). Each size is a level running uniformly partitioned overlap-save
// with its own frequency-domain delay line (FDL) at its own block rate: every P frames it
// transforms the last 2P input frames once per input (FFT of 2P), multiplies the newest
// FDL spectra with its filter partitions and inverse-transforms once per output
// (convolver_level.h). A uniform convolver at B streams every filter spectrum from memory
// every block (2 s 16 x 2 filters at B = 256: about 37 MB per 5.3 ms block, so barely real
// time); a partition of P taps is streamed once per P frames instead. Each level's work
// for one of its blocks is spread over at least a quarter of its period, so a call costs
// at most a few times the average. max_partition_size <= B gives the uniform convolver.
// bench_binaural_convolution measures both renderer structures.
//
// The plan is chosen for the longest filter of the matrix given to the constructor; a
// later, longer matrix gets more partitions of the plan's largest size.
//
// Timing ("latency is exactly one block"). process() adds no delay: frame j of the block
// returned by the k-th call (k = 0, 1, ...) is y[kB + j], where y = x * h is the linear
// convolution of the whole input stream so far, so an impulse at stream frame n appears as
// h starting at output stream frame n. What remains is the one block of buffering any block
// processor has: in a duplex sound-card loop the block captured during period k is
// processed at its end and played during period k+1, so every input sample leaves exactly
// B frames after it entered (not counting driver and converter latency).
//
// Filter swap. A new matrix is first transformed (prepare(): the FFTs of its partitions,
// most of a swap's cost, some 15 ms for a 1 x 16 matrix of 2 s filters), which touches no
// convolver and may run on any thread. setFilters() of the prepared matrix then computes
// its share of the larger levels' outputs already in flight (their input is in the FDLs)
// and allocates its output ring: the part of a swap that needs the convolver's state,
// a few blocks' work (bench_binaural_convolution, BM_SwapPreparedThirdOrderRoomResponse).
// setFilters() of a FilterMatrix does both on the calling thread. The swap starts with the
// next process() call: over `crossfade_blocks` blocks the outputs of both matrices,
// computed on the same delay lines, are mixed with raised-cosine gains that sum to one
// (an equal-gain fade: the two outputs are convolutions of one input and strongly
// correlated, so an equal-power fade would swell by up to 3 dB). Because the delay lines
// hold the input history, not the output, the old filter's tail keeps ringing through the
// fade and the new filter starts with its full tail: there is no gap and no click. A swap
// asked for during a fade waits for that fade to end (only the latest such request is
// kept; it keeps up with the stream meanwhile). A fade costs the old matrix's share of
// the blocks whose output it overlaps.
//
// process() allocates nothing and frees nothing. Not thread-safe: call setFilters() and
// process() from one thread, or under the caller's lock.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/partition_plan.h"

namespace room_reverb::core {

// filters[i][o]: the FIR from input channel i to output channel o. Filters of one matrix
// may differ in length; each needs at least one tap (a single 0 for "no path").
using FilterMatrix = std::vector<std::vector<std::vector<float>>>;

// A filter matrix in the frequency domain, for one partition plan and block size
// (PartitionedConvolver::prepare). Immutable: made on one thread, used on another, shared
// by any number of convolvers of that plan.
struct PreparedFilters;

class ConvolverLevel;
class SampleRing;
struct LevelTarget;

class PartitionedConvolver {
 public:
  static constexpr std::size_t kDefaultBlockSize = 256;
  // 16384 frames (FFTs of 32768): larger partitions save little more for room responses
  // of a few seconds, and the largest work unit (one such FFT, about 0.1 ms) adds to what
  // one call can cost beyond the average.
  static constexpr std::size_t kDefaultMaxPartitionSize = 16384;

  // max_partition_size bounds the partition sizes (see above). Throws InputError for a
  // block size or crossfade length of zero, a matrix with no inputs or outputs, rows with
  // different output counts, empty filters or non-finite taps.
  explicit PartitionedConvolver(const FilterMatrix& filters,
                                std::size_t block_size = kDefaultBlockSize,
                                std::size_t crossfade_blocks = 1,
                                std::size_t max_partition_size = kDefaultMaxPartitionSize);
  // Running the plan `first` was prepared for, from `first` (InputError for a null one or
  // a crossfade of zero blocks).
  PartitionedConvolver(std::shared_ptr<const PreparedFilters> first, std::size_t crossfade_blocks);

  // `filters` transformed for `plan` (from planPartitions) at `block_size`: the work of a
  // swap that needs no convolver. Thread-safe. The same InputErrors as the constructor's
  // checks of a matrix, and for an empty plan.
  static std::shared_ptr<const PreparedFilters> prepare(const FilterMatrix& filters,
                                                        const std::vector<PartitionLevel>& plan,
                                                        std::size_t block_size);
  ~PartitionedConvolver();
  PartitionedConvolver(const PartitionedConvolver&) = delete;
  PartitionedConvolver& operator=(const PartitionedConvolver&) = delete;

  std::size_t inputCount() const { return input_count_; }
  std::size_t outputCount() const { return output_count_; }
  std::size_t blockSize() const { return block_size_; }
  std::size_t crossfadeBlocks() const { return crossfade_blocks_; }
  // Partitions of the longest filter currently in use, over all sizes.
  std::size_t partitionCount() const;
  // The partition sizes and where they start, as planned at construction (the last
  // level's count is the planned one; partitionCount() follows the filters in use).
  const std::vector<PartitionLevel>& partitionPlan() const { return plan_; }
  bool crossfading() const { return fade_block_ < crossfade_blocks_; }

  // Replaces the matrix, with the crossfade described above. The new matrix must have the
  // same numbers of inputs and outputs (InputError otherwise); its filters may be longer or
  // shorter. Filters longer than the plan covers get more partitions of its largest size,
  // whose delay line grows keeping the history it held (older input counts as silence).
  void setFilters(const FilterMatrix& filters);
  // The same for a matrix prepared for this convolver's plan and block size (InputError
  // for another plan, block size or channel counts, or a null one). It keeps a reference
  // to the prepared spectra rather than copying them.
  void setFilters(std::shared_ptr<const PreparedFilters> prepared);

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
  struct FilterSet;

  void setUp(const std::vector<PartitionLevel>& plan);
  std::unique_ptr<FilterSet> makeSet(std::shared_ptr<const PreparedFilters> prepared);
  void startPendingFade();
  std::size_t levelTargets(std::size_t level);

  std::size_t input_count_;
  std::size_t output_count_;
  std::size_t block_size_;
  std::size_t crossfade_blocks_;
  std::vector<PartitionLevel> plan_;
  std::vector<std::unique_ptr<ConvolverLevel>> levels_;

  // Filter sets: the one in use, the one fading out (kept allocated after the fade so
  // process() never frees), and a swap waiting for the current fade to end (kept up to
  // date with the stream while it waits).
  std::unique_ptr<FilterSet> current_;
  std::unique_ptr<FilterSet> previous_;
  std::unique_ptr<FilterSet> pending_;
  bool swap_waiting_ = false;          // pending_ holds a set to fade to
  std::size_t fade_block_;             // blocks of the fade done; == crossfade_blocks_ when idle
  std::int64_t fade_end_frame_ = 0;    // first stream frame after the fade
  std::vector<float> fade_in_gain_;    // per fade sample, the new set's gain

  std::int64_t calls_ = 0;             // process() calls so far: the next block is frame calls_ x B
  std::unique_ptr<SampleRing> input_;  // the input history the levels transform

  // Scratch, preallocated.
  std::vector<LevelTarget> targets_;           // the sets taking part in one level's call
  std::vector<float> fade_out_samples_;        // outputs x B, the old set's output
  std::vector<float*> fade_out_pointers_;
  std::vector<const float*> input_pointers_;   // for the AudioBuffer overload of process()
  std::vector<float*> output_pointers_;
};

}  // namespace room_reverb::core
