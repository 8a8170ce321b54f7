#include "room_reverb/audio/partition_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

namespace {

// Cost units are one complex multiply-add bin. A real FFT of n points measured 0.1-0.13 ns
// x n log2 n for n = 512 ... 65536 (FFTW_ESTIMATE, one core, with the copies around it)
// against 0.35-0.8 ns per multiply-add bin (the low end with the spectra in cache, the high
// end streamed from memory, as the larger levels' are); 0.3 picked the fastest measured
// plans for 1 x 16, 1 x 2 and 16 x 2 matrices of 2 s filters at B = 256.
constexpr double kFftCostPerPointAndStage = 0.3;
// A level's work for one block may be spread over 1/kSpreadFraction of its period.
constexpr std::size_t kSpreadFraction = 4;
constexpr std::size_t kMaxLargerSizes = 16;

std::size_t ceilDiv(std::size_t a, std::size_t b) { return (a + b - 1) / b; }

// The plan for one sequence of larger sizes, or an empty plan when the filter ends
// before a size is reached (the same plan then comes from a shorter sequence).
std::vector<PartitionLevel> planForSizes(std::size_t filter_length, std::size_t block_size,
                                         const std::vector<std::size_t>& sizes) {
  std::vector<PartitionLevel> levels{{block_size, 0, 0}};
  for (std::size_t size : sizes) {
    PartitionLevel& last = levels.back();
    // The fewest partitions of the current size that let `size` start.
    const std::size_t start = earliestFirstTap(size, block_size);
    last.partitions = start > last.first_tap ? ceilDiv(start - last.first_tap, last.partition_size) : 1;
    if (last.endTap() >= filter_length) return {};
    levels.push_back({size, last.endTap(), 0});
  }
  PartitionLevel& last = levels.back();
  last.partitions = ceilDiv(filter_length - last.first_tap, last.partition_size);
  return levels;
}

}  // namespace

std::size_t earliestFirstTap(std::size_t partition_size, std::size_t block_size) {
  // s calls need D = P + (s - 2) B (see the header); P >= 2B keeps it positive.
  const std::size_t spread = std::max<std::size_t>(1, partition_size / block_size / kSpreadFraction);
  return partition_size + spread * block_size - 2 * block_size;
}

std::size_t spreadCalls(const PartitionLevel& level, std::size_t block_size) {
  // Level 0 (P = B, D = 0) gives 1; plans never start a level before P - B.
  const std::size_t reach = level.first_tap + 2 * block_size;
  const std::size_t calls = reach > level.partition_size ? (reach - level.partition_size) / block_size : 1;
  return std::clamp<std::size_t>(calls, 1, level.partition_size / block_size);
}

double fftCost(std::size_t fft_size) {
  return kFftCostPerPointAndStage * fft_size * std::log2(static_cast<double>(std::max<std::size_t>(fft_size, 2)));
}

double multiplyAddCost(std::size_t bins) { return static_cast<double>(bins); }

double partitionPlanCost(const std::vector<PartitionLevel>& levels, std::size_t inputs, std::size_t outputs) {
  double cost = 0.0;
  for (const auto& level : levels) {
    const std::size_t p = level.partition_size;
    const double per_block = (inputs + outputs) * fftCost(2 * p) +
                             inputs * outputs * level.partitions * multiplyAddCost(p + 1);
    cost += per_block / p;
  }
  return cost;
}

std::vector<PartitionLevel> planPartitions(std::size_t filter_length, std::size_t block_size,
                                           std::size_t max_partition_size, std::size_t inputs,
                                           std::size_t outputs) {
  if (filter_length == 0) throw InputError("cannot partition a filter of 0 taps; give at least one tap");
  if (block_size == 0) throw InputError("partition block size is 0; use a positive size such as 256 frames");
  // Candidate sizes above the block, ascending: only those that can start before the
  // filter ends, and at most kMaxLargerSizes of them (2^16 blocks is far beyond any
  // useful partition) so the exhaustive search stays small.
  std::vector<std::size_t> larger;
  for (std::size_t size = 2 * block_size;
       size <= max_partition_size && earliestFirstTap(size, block_size) < filter_length && larger.size() < kMaxLargerSizes;
       size *= 2) {
    larger.push_back(size);
  }

  std::vector<PartitionLevel> best;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> sizes;
  for (std::size_t mask = 0; mask < (std::size_t{1} << larger.size()); ++mask) {
    sizes.clear();
    for (std::size_t k = 0; k < larger.size(); ++k) {
      if (mask & (std::size_t{1} << k)) sizes.push_back(larger[k]);
    }
    auto levels = planForSizes(filter_length, block_size, sizes);
    if (levels.empty()) continue;
    const double cost = partitionPlanCost(levels, inputs, outputs);
    if (cost < best_cost) {
      best_cost = cost;
      best = std::move(levels);
    }
  }
  return best;
}

}  // namespace room_reverb::core
