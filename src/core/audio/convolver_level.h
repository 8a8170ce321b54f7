#pragma once
// One level of the non-uniformly partitioned convolver (partitioned_convolver.h,
// partition_plan.h): the taps [D, D + n P) of every filter, run as uniformly partitioned
// overlap-save with its own frequency-domain delay line (FDL) at its own block rate of
// P = r B frames (Wefers 2015; with P = B and D = 0 it is the classic UPOLS head).
//
// Level block m is input frames [mP, (m+1)P). Its work (one forward FFT of 2P frames per
// input into the FDL; per output, multiply-adds of the n newest FDL spectra with the
// filter partitions, then one inverse FFT) gives output frames [mP + D, mP + D + P),
// which it adds into each filter set's output ring. The work starts in the call that
// completes the block and may take spreadCalls() calls (partition_plan.h): it is cut into
// units (one forward FFT, one input's multiply-adds for a group of outputs, the group's
// inverse FFTs) that run in order, each call running units until its share of the
// block's cost is done.
//
// Several filter sets (the one playing, the one fading out, one waiting to fade in) run
// on one FDL; the caller says which take part in each call's units.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "room_reverb/audio/fft.h"
#include "room_reverb/audio/partition_plan.h"
#include "room_reverb/audio/partitioned_convolver.h"
#include "sample_ring.h"
#include "spectral_kernels.h"

namespace room_reverb::core {

// One filter set's spectra for one level: for output o, input i, partition q (in that
// nesting, the order a unit walks them) a split spectrum of stride() real parts then
// stride() imaginary parts. Zero partitions: the set's filters end before this level.
struct LevelSpectra {
  std::size_t partitions = 0;
  std::vector<float> rows;
  // Per output o and input i (o * inputs + i): the partitions up to the filter's last
  // non-zero tap; those after it are zero and skipped. Per output: the most of its inputs;
  // an output with none here is silent and its inverse transform skipped. A first-order
  // room in a third-order stream has twelve all-zero filters: they cost nothing.
  std::vector<std::size_t> used;
  std::vector<std::size_t> output_used;
  // Per output o and input i: the partitions before the filter's first non-zero tap, also
  // skipped (at most `used`). An RSAO's late part is zero before its onset, the first
  // reflection 10-40 ms after the RIR's start, which is up to all of the first level.
  std::vector<std::size_t> leading;
};

// Where a level's work for one filter set goes.
struct LevelTarget {
  const LevelSpectra* spectra = nullptr;
  float* accumulator = nullptr;  // accumulatorFloats(): the output spectra being summed
  SampleRing* output = nullptr;  // the set's output, by stream frame
};

class ConvolverLevel {
 public:
  // `open_ended`: the last level, whose partition count follows the filters; other
  // levels stop at plan.partitions.
  ConvolverLevel(const PartitionLevel& plan, bool open_ended, std::size_t block_size, std::size_t inputs,
                 std::size_t outputs);
  ConvolverLevel(const ConvolverLevel&) = delete;
  ConvolverLevel& operator=(const ConvolverLevel&) = delete;

  const PartitionLevel& plan() const { return plan_; }
  std::size_t stride() const { return stride_; }
  // A target's accumulator: the spectra of one group of outputs (spectral_kernels.h).
  std::size_t accumulatorFloats() const { return kOutputGroup * 2 * stride_; }

  // The level block whose work runs in process() call `call` (-1 before the first), and
  // the first output frame of a block.
  std::int64_t blockOfCall(std::int64_t call) const { return (call + 1) / static_cast<std::int64_t>(calls_per_block_) - 1; }
  std::int64_t outputBegin(std::int64_t block) const {
    return block * static_cast<std::int64_t>(plan_.partition_size) + static_cast<std::int64_t>(plan_.first_tap);
  }

  // A level's share of `filters` (longest: the longest filter's taps), for a level of
  // `plan` (open-ended: the last). Allocates, and touches no level, so it may run on any
  // thread; the level that runs it then reserve()s its FDL for the partitions.
  static LevelSpectra transform(const PartitionLevel& plan, bool open_ended, std::size_t inputs, std::size_t outputs,
                                const FilterMatrix& filters, std::size_t longest);
  // Grows the FDL, keeping its history, so sets of `partitions` partitions can run.
  void reserve(std::size_t partitions);

  // Call `call`'s share of its block's work, for `count` targets.
  void run(std::int64_t call, const SampleRing& input, const LevelTarget* targets, std::size_t count);
  // Before call `next_call`, gives a newly added set everything in flight: the output
  // frames from next_call x B on of every block whose work has started (the blocks from
  // blockOfCall(next_call - 1) + 1 on are the caller's to run for it).
  void catchUp(std::int64_t next_call, const SampleRing& input, const LevelTarget& target);
  // Forgets the FDL and abandons the block in progress (its outputs would be silence).
  void reset();

 private:
  std::size_t slotOf(std::int64_t block) const;
  const float* slotRow(std::int64_t block, std::size_t input) const;
  float* slotRow(std::int64_t block, std::size_t input);
  double unitCost(std::size_t unit) const;
  void runUnit(std::size_t unit, const SampleRing& input, const LevelTarget* targets, std::size_t count);
  void finishInputTransforms(const SampleRing& input);
  void transformInput(std::int64_t block, std::size_t input, const SampleRing& ring);
  std::size_t groupSize(std::size_t group) const;
  void multiplyAdd(std::int64_t block, std::size_t group, std::size_t input, const LevelTarget& target) const;
  void finishOutputs(std::int64_t block, std::size_t group, const LevelTarget& target, std::int64_t from_frame);

  PartitionLevel plan_;
  bool open_ended_;
  std::size_t block_size_;       // B
  std::size_t calls_per_block_;  // r = P / B
  std::size_t spread_;  // calls a block's work is spread over
  std::size_t inputs_;
  std::size_t outputs_;
  std::size_t bins_;    // P + 1 bins of a 2P real FFT
  std::size_t stride_;  // bins_ rounded up (spectral_kernels.h)
  RealFft fft_;
  std::size_t groups_;  // outputs in groups of kOutputGroup (spectral_kernels.h)

  // FDL: capacity_ slots, block m in slot m mod capacity_, each one split spectrum per input.
  std::size_t capacity_ = 0;
  std::vector<float> delay_line_;

  // Progress through the current block's units: inputs_ forward FFTs, then per group of
  // outputs inputs_ multiply-add units (one input, all partitions) and one unit of the
  // group's inverse FFTs. Costs in
  // partition_plan.h's units, for the per-call shares.
  std::int64_t block_ = -1;
  std::size_t units_;
  std::size_t next_unit_;
  double fft_unit_cost_;
  double mac_unit_cost_ = 0.0;
  double block_cost_ = 0.0;
  double done_cost_ = 0.0;
};

}  // namespace room_reverb::core
