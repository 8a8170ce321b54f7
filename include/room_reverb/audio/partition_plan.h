#pragma once
// Non-uniform partitioning of long FIR filters for the streaming convolver
// (partitioned_convolver.h): which partition sizes cover which taps.
//
// A uniformly partitioned convolver with block B does, per block, one multiply-add of B+1
// bins per partition, so a filter of L taps costs about L/B spectrum passes per block, all
// streamed from memory. Non-uniform partitioning (Gardner 1995, "Efficient convolution
// without input-output delay"; Garcia 2002, "Optimal filter partition for efficient
// convolution with short input/output delay"; Wefers 2015, "Partitioned convolution
// algorithms for real-time auralization") keeps partitions of B at the head of the
// filter, where the zero delay needs them, and covers later taps with ever larger
// partitions, each size running its own overlap-save delay line at its own block rate:
// a partition of P taps costs about one FFT of 2P and P+1 bins of multiply-add per P
// frames, so the work per frame falls as P grows.
//
// Scheduling. A level of size P transforms its input every P/B blocks. If its first
// partition starts at tap D, its output for an input block is first needed (D - P)/B + 1
// calls after the call that completed the block, so its work (FFTs and multiply-adds) can
// be spread over s = (D - P)/B + 2 process() calls: the completing call can start it and
// the first call that outputs can finish it. D = P - B (s = 1) is Gardner's (1995) schedule,
// where a level's whole block of work lands on one call; D = 2P - 2B (s = P/B) spreads it
// over the level's whole period, the time-distributed scheduling of Wefers (2015). A larger
// D costs more partitions of the smaller sizes before the level may start, and those are
// streamed from memory every block. Here each level may start once its work can be spread
// over a quarter of its period: measured for a 1 x 16 matrix of 2 s filters at B = 256 (the
// renderer's long convolution) full spreading costs 15-20 % more CPU on average, while a
// quarter keeps the busiest call under a tenth of the block period. No call does more than
// its share of each level's work plus one unit (one FFT or one input's multiply-adds).
#include <cstddef>
#include <vector>

namespace room_reverb::core {

// One uniform segment of a partitioned filter: `partitions` partitions of `partition_size`
// taps, the first starting at tap `first_tap`.
struct PartitionLevel {
  std::size_t partition_size = 0;
  std::size_t first_tap = 0;
  std::size_t partitions = 0;

  std::size_t endTap() const { return first_tap + partitions * partition_size; }
};

// The first tap a level of partition_size (a multiple of block_size above it) may start
// at: where its work can be spread over a quarter of its period (and at least one call).
std::size_t earliestFirstTap(std::size_t partition_size, std::size_t block_size);

// The calls a level's work for one input block may be spread over, given where it starts
// (at least 1, at most partition_size / block_size).
std::size_t spreadCalls(const PartitionLevel& level, std::size_t block_size);

// Relative costs of the convolver's work units, in one unit so plans can be compared:
// one real FFT of `fft_size` points (forward or inverse, with the copies around it) and
// one complex multiply-add over `bins` bins. Calibrated on FFTW 3.3 (FFTW_ESTIMATE
// plans) against the convolver's own vectorised multiply-add: a 2P-point real FFT costs
// as much as 0.6 log2(2P) multiply-add passes over its P+1 bins (5 at P = 256, 9 at
// P = 16384).
double fftCost(std::size_t fft_size);
double multiplyAddCost(std::size_t bins);

// Work per output frame of running `levels` for a matrix of inputs x outputs filters:
// per level and per P frames, one forward FFT per input, one inverse per output and
// inputs x outputs x partitions multiply-adds.
double partitionPlanCost(const std::vector<PartitionLevel>& levels, std::size_t inputs,
                         std::size_t outputs);

// The cheapest plan (by partitionPlanCost) covering `filter_length` taps with partitions
// of block_size x 2^k frames, k >= 0, none above max_partition_size (block_size itself is
// always allowed, so a maximum <= block_size gives uniform partitioning). Level 0 has
// partitions of block_size from tap 0; each later level is larger than the one before
// and starts at its earliestFirstTap() or, when the partitions before it overshoot that,
// just after them; the last level covers the rest of the filter. Like Garcia (2002) it
// minimises a cost model over partitionings, here by trying every sequence of sizes with
// the number of partitions of each size fixed by the next size's start (the fewest that
// reach it), at most 2^16 candidates. Throws InputError for a zero filter length or
// block size.
std::vector<PartitionLevel> planPartitions(std::size_t filter_length, std::size_t block_size,
                                           std::size_t max_partition_size, std::size_t inputs,
                                           std::size_t outputs);

}  // namespace room_reverb::core
