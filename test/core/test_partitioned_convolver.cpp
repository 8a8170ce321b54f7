#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <thread>

#include "room_reverb/audio/convolution.h"
#include "room_reverb/audio/partition_plan.h"
#include "room_reverb/audio/partitioned_convolver.h"
#include "room_reverb/common/error.h"
#include "synthetic_rir.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;
using room_reverb::test::whiteNoise;

// Counts heap allocations of this test process, so a test can assert that process() makes
// none (replacing the global operator new is the only way to see every allocation). The
// deletes are kept out of line: inlined, GCC would pair the replaced new with free() and
// warn of a mismatch.
namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void operator delete(void* p) noexcept { std::free(p); }
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

using Channels = std::vector<std::vector<float>>;

FilterMatrix randomFilters(std::size_t inputs, std::size_t outputs, std::size_t min_length,
                           std::size_t max_length, std::uint32_t seed) {
  FilterMatrix filters(inputs, Channels(outputs));
  std::uint32_t s = seed;
  for (auto& row : filters) {
    for (auto& filter : row) {
      const std::size_t length = min_length + (s * 2654435761u) % (max_length - min_length + 1);
      filter = whiteNoise(length, s++);
      for (std::size_t n = 0; n < length; ++n) filter[n] *= static_cast<float>(std::exp(-3.0 * n / length));
    }
  }
  return filters;
}

// Streams `inputs` (lengths a multiple of the block size) through the convolver.
Channels stream(PartitionedConvolver& convolver, const Channels& inputs) {
  const std::size_t b = convolver.blockSize();
  Channels out(convolver.outputCount(), std::vector<float>(inputs.front().size()));
  AudioBuffer in_block = makeSilentBuffer(inputs.size(), b, 48000.0);
  AudioBuffer out_block;
  for (std::size_t start = 0; start < inputs.front().size(); start += b) {
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      std::copy_n(inputs[i].begin() + start, b, in_block.channels[i].begin());
    }
    convolver.process(in_block, out_block);
    for (std::size_t o = 0; o < out.size(); ++o) std::copy_n(out_block.channels[o].begin(), b, out[o].begin() + start);
  }
  return out;
}

// The offline result, truncated to the input length: out[o] = sum_i x[i] * h[i][o].
Channels offline(const FilterMatrix& filters, const Channels& inputs) {
  const std::size_t length = inputs.front().size();
  Channels out(filters.front().size(), std::vector<float>(length, 0.0f));
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    for (std::size_t o = 0; o < out.size(); ++o) {
      const auto y = fftConvolve(inputs[i], filters[i][o]);
      for (std::size_t n = 0; n < length; ++n) out[o][n] += y[n];
    }
  }
  return out;
}

// Error energy relative to the reference's, in dB, over [begin, end) of every channel.
double errorDb(const Channels& got, const Channels& want, std::size_t begin, std::size_t end) {
  double error = 0.0;
  double energy = 0.0;
  for (std::size_t c = 0; c < want.size(); ++c) {
    for (std::size_t n = begin; n < end; ++n) {
      error += std::pow(double(got[c][n]) - want[c][n], 2);
      energy += std::pow(double(want[c][n]), 2);
    }
  }
  return 10.0 * std::log10(error / energy);
}

double largestStep(const std::vector<float>& x) {
  double step = 0.0;
  for (std::size_t n = 1; n < x.size(); ++n) step = std::max(step, double(std::abs(x[n] - x[n - 1])));
  return step;
}

// The convolver's fade-in gain at sample n of a fade of `length` samples (the header's
// raised cosine).
double fadeInGain(std::size_t n, std::size_t length) { return 0.5 - 0.5 * std::cos(M_PI * (n + 0.5) / length); }

Channels noiseInputs(std::size_t channels, std::size_t blocks, std::size_t block_size, std::size_t silent_blocks) {
  Channels inputs;
  for (std::size_t c = 0; c < channels; ++c) {
    auto x = whiteNoise(blocks * block_size, 100 + static_cast<std::uint32_t>(c));
    x.resize((blocks + silent_blocks) * block_size, 0.0f);  // let the tails ring out
    inputs.push_back(std::move(x));
  }
  return inputs;
}

}  // namespace

TEST(PartitionedConvolver, StreamingEqualsOfflineConvolution) {
  struct Case {
    std::size_t inputs, outputs, block, min_taps, max_taps;
  };
  // Filters shorter than a block, longer than several, and mixed lengths in one matrix.
  const std::vector<Case> cases = {{16, 2, 64, 700, 1100},  {16, 2, 256, 20, 200},  {16, 2, 256, 300, 1300},
                                   {16, 2, 512, 600, 1600}, {1, 2, 64, 64, 64},     {1, 2, 512, 5000, 5000},
                                   {4, 3, 100, 1, 450}};
  double worst_db = -1000.0;
  for (const auto& c : cases) {
    const auto filters = randomFilters(c.inputs, c.outputs, c.min_taps, c.max_taps, 7);
    PartitionedConvolver convolver(filters, c.block);
    const auto inputs = noiseInputs(c.inputs, 10, c.block, (c.max_taps + c.block - 1) / c.block);
    const double db = errorDb(stream(convolver, inputs), offline(filters, inputs), 0, inputs.front().size());
    EXPECT_LT(db, -100.0) << c.inputs << "x" << c.outputs << " block " << c.block << " taps " << c.max_taps;
    worst_db = std::max(worst_db, db);
  }
  RecordProperty("worst_error_db", std::to_string(worst_db));
  std::cout << "worst streaming-vs-offline error: " << worst_db << " dB\n";
}

TEST(PartitionedConvolver, ImpulseComesOutAsTheFilterWithNoAddedDelay) {
  // The documented timing: frame j of call k is y[kB + j], so an impulse at stream frame
  // n gives the filter from output frame n on (the one block of latency is the caller's
  // buffering, not a shift inside the stream).
  const std::size_t b = 64;
  const auto filters = randomFilters(1, 2, 150, 150, 3);
  PartitionedConvolver convolver(filters, b);
  const std::size_t at = b + b / 2 + 5;
  Channels input(1, std::vector<float>(6 * b, 0.0f));
  input[0][at] = 1.0f;
  const auto out = stream(convolver, input);
  for (std::size_t o = 0; o < 2; ++o) {
    for (std::size_t n = 0; n < out[o].size(); ++n) {
      const float want = n >= at && n - at < 150 ? filters[0][o][n - at] : 0.0f;
      ASSERT_NEAR(out[o][n], want, 1e-5) << "output " << o << " frame " << n;
    }
  }
}

TEST(PartitionedConvolver, FilterSwapCrossfadesWithoutClickOrGap) {
  // A 1 kHz sine through a gain of 1, swapped for a gain of 0.5 delayed by 7 frames.
  const std::size_t b = 256;
  const std::size_t swap_block = 20;
  const FilterMatrix old_filters = {{{1.0f}}};
  const FilterMatrix new_filters = {{{0, 0, 0, 0, 0, 0, 0, 0.5f}}};
  Channels input(1, std::vector<float>(40 * b));
  for (std::size_t n = 0; n < input[0].size(); ++n) input[0][n] = static_cast<float>(0.8 * std::sin(2 * M_PI * 1000.0 * n / 48000.0));
  const auto old_out = offline(old_filters, input);
  const auto new_out = offline(new_filters, input);
  const double own_step = std::max(largestStep(old_out[0]), largestStep(new_out[0]));
  double old_rms = 0.0, new_rms = 0.0;
  for (std::size_t n = 0; n < input[0].size(); ++n) old_rms += old_out[0][n] * old_out[0][n] / input[0].size();
  for (std::size_t n = 0; n < input[0].size(); ++n) new_rms += new_out[0][n] * new_out[0][n] / input[0].size();
  const double quieter_rms = std::sqrt(std::min(old_rms, new_rms));

  for (std::size_t fade_blocks : {1u, 4u}) {
    PartitionedConvolver convolver(old_filters, b, fade_blocks);
    const Channels first(1, std::vector<float>(input[0].begin(), input[0].begin() + swap_block * b));
    const Channels second(1, std::vector<float>(input[0].begin() + swap_block * b, input[0].end()));
    auto out = stream(convolver, first)[0];
    convolver.setFilters(new_filters);
    const auto rest = stream(convolver, second)[0];
    out.insert(out.end(), rest.begin(), rest.end());

    const std::size_t fade_end = (swap_block + fade_blocks) * b;
    for (std::size_t n = 0; n < out.size(); ++n) {
      if (n < swap_block * b) {
        ASSERT_NEAR(out[n], old_out[0][n], 1e-5) << n;
      } else if (n >= fade_end) {
        ASSERT_NEAR(out[n], new_out[0][n], 1e-5) << n;
      }
    }
    const double step_ratio = largestStep(out) / own_step;
    EXPECT_LE(step_ratio, 1.0) << "fade over " << fade_blocks << " blocks";
    std::cout << "fade over " << fade_blocks << " blocks: largest step / signal's own largest step = " << step_ratio << "\n";
    // No gap: the RMS over every 48-frame window (one period) stays near the signal level.
    for (std::size_t start = 0; start + 48 <= out.size(); start += 16) {
      double energy = 0.0;
      for (std::size_t n = start; n < start + 48; ++n) energy += out[n] * out[n] / 48.0;
      ASSERT_GT(std::sqrt(energy), 0.5 * quieter_rms) << "window at " << start;
    }
  }
}

TEST(PartitionedConvolver, NewFilterStartsWithItsFullTail) {
  // The delay line holds the input history, so right after the fade the output is the
  // offline convolution of the whole stream with the new filters, even a longer one.
  const std::size_t b = 128;
  const auto old_filters = randomFilters(2, 2, 200, 400, 11);
  const auto new_filters = randomFilters(2, 2, 500, 900, 12);
  const auto inputs = noiseInputs(2, 30, b, 0);
  PartitionedConvolver convolver(old_filters, b, 2);
  Channels head(2), tail(2);
  for (std::size_t i = 0; i < 2; ++i) {
    head[i].assign(inputs[i].begin(), inputs[i].begin() + 12 * b);
    tail[i].assign(inputs[i].begin() + 12 * b, inputs[i].end());
  }
  stream(convolver, head);
  convolver.setFilters(new_filters);
  EXPECT_TRUE(convolver.crossfading());
  const auto got_tail = stream(convolver, tail);
  EXPECT_FALSE(convolver.crossfading());
  const auto want = offline(new_filters, inputs);
  Channels want_tail(2);
  for (std::size_t o = 0; o < 2; ++o) want_tail[o].assign(want[o].begin() + 12 * b, want[o].end());
  EXPECT_LT(errorDb(got_tail, want_tail, 2 * b, want_tail[0].size()), -100.0);
}

TEST(PartitionedConvolver, SwapRequestedDuringAFadeWaitsForIt) {
  const std::size_t b = 64;
  const auto a = randomFilters(1, 2, 100, 100, 1);
  const auto c = randomFilters(1, 2, 300, 300, 3);
  PartitionedConvolver convolver(a, b, 3);
  const auto inputs = noiseInputs(1, 20, b, 0);
  convolver.setFilters(randomFilters(1, 2, 200, 200, 2));
  convolver.setFilters(c);  // arrives during the first fade
  const auto out = stream(convolver, inputs);
  // Three blocks of the first fade, then three of the second: from block 6 on it is c.
  EXPECT_LT(errorDb(out, offline(c, inputs), 6 * b, inputs.front().size()), -100.0);
  EXPECT_GT(errorDb(out, offline(c, inputs), 3 * b, 6 * b), -100.0);
  EXPECT_EQ(convolver.partitionCount(), 5u);
}

TEST(PartitionedConvolver, ProcessAllocatesNothingEvenDuringAFade) {
  const std::size_t b = 128;
  PartitionedConvolver convolver(randomFilters(4, 2, 300, 700, 5), b, 2);
  AudioBuffer in = makeSilentBuffer(4, b, 48000.0);
  in.channels[0][3] = 1.0f;
  AudioBuffer out;
  convolver.process(in, out);  // shapes `out` once
  convolver.setFilters(randomFilters(4, 2, 100, 900, 6));
  const long before = g_allocations.load();
  for (int k = 0; k < 6; ++k) convolver.process(in, out);
  convolver.reset();
  convolver.process(in, out);
  EXPECT_EQ(g_allocations.load(), before);
}

TEST(PartitionedConvolver, ResetForgetsTheInput) {
  const std::size_t b = 64;
  const auto filters = randomFilters(1, 1, 300, 300, 4);
  PartitionedConvolver convolver(filters, b);
  const auto inputs = noiseInputs(1, 4, b, 0);
  stream(convolver, inputs);
  convolver.reset();
  const auto out = stream(convolver, inputs);
  EXPECT_LT(errorDb(out, offline(filters, inputs), 0, inputs.front().size()), -100.0);
}

TEST(PartitionedConvolver, RejectsBadInputs) {
  const FilterMatrix two_by_two = {{{1.0f}, {0.5f}}, {{0.2f}, {0.1f}}};
  expectInputError([&] { PartitionedConvolver(two_by_two, 0); }, {"block size is 0"});
  expectInputError([&] { PartitionedConvolver(two_by_two, 64, 0); }, {"crossfade is 0"});
  expectInputError([] { PartitionedConvolver(FilterMatrix{}, 64); }, {"no input channels"});
  expectInputError([] { PartitionedConvolver(FilterMatrix{{}}, 64); }, {"no output channels"});
  expectInputError([] { PartitionedConvolver(FilterMatrix{{{1.0f}, {1.0f}}, {{1.0f}}}, 64); }, {"row 1 has 1 filters", "row 0 has 2"});
  expectInputError([] { PartitionedConvolver(FilterMatrix{{{1.0f}, {}}}, 64); }, {"filter 0->1 is empty"});
  expectInputError([] { PartitionedConvolver(FilterMatrix{{{1.0f, NAN}}}, 64); }, {"non-finite"});

  PartitionedConvolver convolver(two_by_two, 64);
  expectInputError([&] { convolver.setFilters({{{1.0f}, {1.0f}, {1.0f}}, {{1.0f}, {1.0f}, {1.0f}}}); },
                   {"2 inputs x 3 outputs", "runs 2 x 2"});
  AudioBuffer out;
  expectInputError([&] { convolver.process(makeSilentBuffer(3, 64, 48000.0), out); }, {"3 channels", "expect 2"});
  expectInputError([&] { convolver.process(makeSilentBuffer(2, 63, 48000.0), out); }, {"63 frames", "exactly 64"});
  // A failed swap leaves the convolver as it was.
  EXPECT_FALSE(convolver.crossfading());
  convolver.process(makeSilentBuffer(2, 64, 48000.0), out);
  EXPECT_EQ(out.channelCount(), 2u);
}

// --- Non-uniform partitioning (partition_plan.h) ---------------------------------------

TEST(PartitionPlan, CoversTheFilterWithGrowingLevelsThatCanSpreadTheirWork) {
  struct Case {
    std::size_t length, block, max_size, inputs, outputs;
  };
  const std::vector<Case> cases = {{96000, 256, 16384, 1, 16}, {96000, 256, 16384, 16, 2}, {96000, 256, 16384, 1, 2},
                                   {20000, 64, 16384, 2, 3},   {12345, 100, 4096, 1, 1},    {700, 256, 16384, 1, 2}};
  for (const auto& c : cases) {
    const auto plan = planPartitions(c.length, c.block, c.max_size, c.inputs, c.outputs);
    ASSERT_FALSE(plan.empty());
    EXPECT_EQ(plan.front().partition_size, c.block);
    EXPECT_EQ(plan.front().first_tap, 0u);
    for (std::size_t l = 0; l < plan.size(); ++l) {
      const auto& level = plan[l];
      EXPECT_GE(level.partitions, 1u);
      EXPECT_LE(level.partition_size, std::max(c.block, c.max_size));
      EXPECT_EQ(level.partition_size % c.block, 0u);
      const std::size_t period = level.partition_size / c.block;
      EXPECT_EQ(period & (period - 1), 0u) << "sizes are the block times a power of two";
      // Its output is never needed before its work is done, which may take a quarter of
      // its period.
      EXPECT_GE(spreadCalls(level, c.block), std::max<std::size_t>(1, period / 4));
      if (l > 0) {
        EXPECT_GT(level.partition_size, plan[l - 1].partition_size);
        EXPECT_EQ(level.first_tap, plan[l - 1].endTap());
        EXPECT_GE(level.first_tap, earliestFirstTap(level.partition_size, c.block));
      }
    }
    EXPECT_GE(plan.back().endTap(), c.length);
    EXPECT_LT(plan.back().endTap() - plan.back().partition_size, c.length) << "no partition beyond the filter";
  }
  // The renderer's long convolution: several sizes, several times cheaper than uniform.
  const auto ambisonic = planPartitions(96000, 256, 16384, 1, 16);
  EXPECT_GE(ambisonic.size(), 3u);
  const double uniform_cost = partitionPlanCost(planPartitions(96000, 256, 256, 1, 16), 1, 16);
  EXPECT_LT(partitionPlanCost(ambisonic, 1, 16), uniform_cost / 5.0);
}

TEST(PartitionPlan, MaximumAtTheBlockSizeIsUniformAndBadSizesAreRejected) {
  const auto uniform = planPartitions(5000, 256, 256, 16, 2);
  ASSERT_EQ(uniform.size(), 1u);
  EXPECT_EQ(uniform.front().partitions, 20u);
  EXPECT_EQ(planPartitions(5000, 256, 0, 1, 1).size(), 1u);
  EXPECT_EQ(planPartitions(100, 256, 16384, 1, 1).size(), 1u) << "a filter inside one block";
  expectInputError([] { planPartitions(0, 256, 16384, 1, 1); }, {"0 taps"});
  expectInputError([] { planPartitions(100, 0, 16384, 1, 1); }, {"block size is 0"});
}

TEST(PartitionedConvolver, NonUniformStreamingEqualsOfflineConvolution) {
  struct Case {
    std::size_t inputs, outputs, block, taps, max_partition;
  };
  // 2 s responses at the renderer's block (both structures), many levels at small blocks,
  // a block that is no power of two, and the uniform convolver on the same filters.
  const std::vector<Case> cases = {{1, 16, 256, 96000, 16384}, {1, 2, 256, 96000, 16384}, {16, 2, 256, 30000, 16384},
                                   {2, 3, 64, 20000, 16384},   {1, 1, 100, 12345, 4096},   {2, 3, 64, 20000, 64}};
  double worst_db = -1000.0;
  for (const auto& c : cases) {
    const auto filters = randomFilters(c.inputs, c.outputs, c.taps, c.taps, 9);
    PartitionedConvolver convolver(filters, c.block, 1, c.max_partition);
    if (c.max_partition > c.block) {
      EXPECT_GE(convolver.partitionPlan().size(), 2u) << "the case should exercise several partition sizes";
    }
    // Noise for about half a filter (so every level sees signal), then the tail rings out.
    const std::size_t blocks = (c.taps / 2 + c.block - 1) / c.block;
    const auto inputs = noiseInputs(c.inputs, blocks, c.block, (c.taps + c.block - 1) / c.block);
    const double db = errorDb(stream(convolver, inputs), offline(filters, inputs), 0, inputs.front().size());
    EXPECT_LT(db, -100.0) << c.inputs << "x" << c.outputs << " block " << c.block << " taps " << c.taps;
    worst_db = std::max(worst_db, db);
  }
  RecordProperty("worst_error_db", std::to_string(worst_db));
  std::cout << "worst non-uniform streaming-vs-offline error: " << worst_db << " dB\n";
}

TEST(PartitionedConvolver, ZeroFiltersAndZeroTailsAreSkippedExactly) {
  // A first-order room padded to third order: outputs 4-15 all zero; outputs 1-3 end in
  // long runs of zeros (skipped partitions), one output zero but for its last tap. Then a
  // swap to the full matrix, which must bring every output in.
  auto filters = randomFilters(1, 16, 40000, 40000, 21);
  auto padded = filters;
  for (std::size_t o = 4; o < 16; ++o) padded[0][o] = {0.0f};
  for (std::size_t o = 1; o < 4; ++o) std::fill(padded[0][o].begin() + 3000 * static_cast<long>(o), padded[0][o].end(), 0.0f);
  std::fill(padded[0][0].begin(), padded[0][0].end() - 1, 0.0f);
  PartitionedConvolver convolver(padded, 256, 1, 16384);
  const auto inputs = noiseInputs(1, 100, 256, 160);
  EXPECT_LT(errorDb(stream(convolver, inputs), offline(padded, inputs), 0, inputs.front().size()), -100.0);
  // After the one-block crossfade the full matrix plays, its tail complete.
  PartitionedConvolver swapped(padded, 256, 1, 16384);
  swapped.setFilters(filters);
  EXPECT_LT(errorDb(stream(swapped, inputs), offline(filters, inputs), 512, inputs.front().size()), -100.0);
}

TEST(PartitionedConvolver, LeadingZerosAreSkippedExactly) {
  // Late parts that start at their onset: each output of a 1 x 16 matrix zero before its
  // own first tap, from none to past the first level (a partition boundary, one sample on
  // either side of it, deep into the last level); in one output group the onsets differ
  // so the group runs partly together. Then 2 x 3 with onsets per input, and swaps both
  // ways between the matrices with and without them.
  const std::vector<std::size_t> onsets = {0,   1,    255,  256,  300,   811,   1880,  2047,
                                           2048, 2049, 2500, 5000, 20480, 30000, 39000, 39999};
  const auto full = randomFilters(1, 16, 40000, 40000, 33);
  auto late = full;
  for (std::size_t o = 0; o < 16; ++o) std::fill_n(late[0][o].begin(), onsets[o], 0.0f);
  const auto inputs = noiseInputs(1, 100, 256, 160);
  PartitionedConvolver convolver(late, 256, 1, 16384);
  EXPECT_LT(errorDb(stream(convolver, inputs), offline(late, inputs), 0, inputs.front().size()), -100.0);
  PartitionedConvolver to_full(late, 256, 1, 16384);
  to_full.setFilters(full);
  EXPECT_LT(errorDb(stream(to_full, inputs), offline(full, inputs), 512, inputs.front().size()), -100.0);
  PartitionedConvolver to_late(full, 256, 1, 16384);
  to_late.setFilters(late);
  EXPECT_LT(errorDb(stream(to_late, inputs), offline(late, inputs), 512, inputs.front().size()), -100.0);

  auto matrix = randomFilters(2, 3, 20000, 20000, 34);
  const std::size_t starts[2][3] = {{0, 700, 5000}, {1500, 0, 19000}};
  for (std::size_t i = 0; i < 2; ++i) {
    for (std::size_t o = 0; o < 3; ++o) std::fill_n(matrix[i][o].begin(), starts[i][o], 0.0f);
  }
  const auto pair = noiseInputs(2, 60, 64, 320);
  PartitionedConvolver small(matrix, 64, 1, 16384);
  EXPECT_LT(errorDb(stream(small, pair), offline(matrix, pair), 0, pair.front().size()), -100.0);
}

TEST(PartitionedConvolver, NonUniformImpulseComesOutAsTheFilterWithNoAddedDelay) {
  // Two impulses at frames that fall mid-block and mid-period of every level: the output
  // is the filter from exactly those frames on, so no level adds or loses a sample.
  const std::size_t b = 64;
  const std::size_t taps = 9000;
  const auto filters = randomFilters(1, 2, taps, taps, 21);
  PartitionedConvolver convolver(filters, b);
  ASSERT_GE(convolver.partitionPlan().size(), 3u);
  const std::size_t first = 3 * b + 17;
  const std::size_t second = 4000 + 5;
  Channels input(1, std::vector<float>(first + second + taps + 3 * b, 0.0f));
  input[0].resize(input[0].size() / b * b);
  input[0][first] = 1.0f;
  input[0][second] = -0.5f;
  const auto out = stream(convolver, input);
  for (std::size_t o = 0; o < 2; ++o) {
    for (std::size_t n = 0; n < out[o].size(); ++n) {
      double want = 0.0;
      if (n >= first && n - first < taps) want += filters[0][o][n - first];
      if (n >= second && n - second < taps) want -= 0.5 * filters[0][o][n - second];
      ASSERT_NEAR(out[o][n], want, 1e-5) << "output " << o << " frame " << n;
    }
  }
}

TEST(PartitionedConvolver, NonUniformSwapIsAnExactCrossfadeAtAnyPhase) {
  // Long filters, so the larger levels have work in flight at the swap. Whatever the
  // phase of the swap within their periods, the output is the old filters' response up to
  // the swap, exactly the raised-cosine mix of both responses during the fade (so no gap
  // and no click: both are the full convolutions of the stream), and the new filters'
  // full response after it.
  const std::size_t b = 64;
  const std::size_t fade_blocks = 3;
  const auto old_filters = randomFilters(2, 2, 6000, 6000, 31);
  const auto new_filters = randomFilters(2, 2, 5000, 6000, 32);
  const auto inputs = noiseInputs(2, 240, b, 0);
  const auto old_out = offline(old_filters, inputs);
  const auto new_out = offline(new_filters, inputs);
  for (std::size_t swap_block : {100u, 131u, 158u, 193u}) {
    PartitionedConvolver convolver(old_filters, b, fade_blocks);
    ASSERT_GE(convolver.partitionPlan().size(), 3u);
    Channels head(2), tail(2);
    for (std::size_t i = 0; i < 2; ++i) {
      head[i].assign(inputs[i].begin(), inputs[i].begin() + swap_block * b);
      tail[i].assign(inputs[i].begin() + swap_block * b, inputs[i].end());
    }
    Channels out = stream(convolver, head);
    convolver.setFilters(new_filters);
    const auto rest = stream(convolver, tail);
    const std::size_t swap = swap_block * b;
    const std::size_t fade = fade_blocks * b;
    Channels want(2);
    for (std::size_t o = 0; o < 2; ++o) {
      out[o].insert(out[o].end(), rest[o].begin(), rest[o].end());
      want[o] = old_out[o];
      for (std::size_t n = swap; n < want[o].size(); ++n) {
        const double g = n < swap + fade ? fadeInGain(n - swap, fade) : 1.0;
        want[o][n] = static_cast<float>(old_out[o][n] + g * (new_out[o][n] - old_out[o][n]));
      }
    }
    EXPECT_LT(errorDb(out, want, 0, swap), -100.0) << "before the swap at block " << swap_block;
    EXPECT_LT(errorDb(out, want, swap, swap + fade), -100.0) << "the fade at block " << swap_block;
    EXPECT_LT(errorDb(out, want, swap + fade, want[0].size()), -100.0) << "after the fade at block " << swap_block;
  }
}

TEST(PartitionedConvolver, NonUniformSwapDuringAFadeKeepsUpWhileItWaits) {
  // The waiting matrix runs with the stream while it waits, so when its own fade starts
  // (after a wait in which the larger levels start blocks) its output is already whole.
  const std::size_t b = 64;
  const std::size_t fade_blocks = 8;
  const auto a = randomFilters(1, 2, 9000, 9000, 41);
  const auto c = randomFilters(1, 2, 8500, 9000, 43);
  const auto inputs = noiseInputs(1, 300, b, 0);
  PartitionedConvolver convolver(a, b, fade_blocks);
  ASSERT_GE(convolver.partitionPlan().size(), 3u);
  auto section = [&](std::size_t from_block, std::size_t to_block) {
    return Channels(1, std::vector<float>(inputs[0].begin() + from_block * b, inputs[0].begin() + to_block * b));
  };
  Channels out = stream(convolver, section(0, 90));
  convolver.setFilters(randomFilters(1, 2, 9000, 9000, 42));
  const auto part = stream(convolver, section(90, 91));
  convolver.setFilters(c);  // one block into an eight-block fade: waits seven
  EXPECT_TRUE(convolver.crossfading());
  const auto rest = stream(convolver, section(91, 300));
  for (std::size_t o = 0; o < 2; ++o) {
    out[o].insert(out[o].end(), part[o].begin(), part[o].end());
    out[o].insert(out[o].end(), rest[o].begin(), rest[o].end());
  }
  // The second fade runs over blocks 98..105; from block 106 on the output is c's.
  EXPECT_LT(errorDb(out, offline(c, inputs), 106 * b, inputs.front().size()), -100.0);
  EXPECT_GT(errorDb(out, offline(c, inputs), 91 * b, 98 * b), -100.0);
}

TEST(PartitionedConvolver, NonUniformProcessAllocatesNothing) {
  const std::size_t b = 64;
  PartitionedConvolver convolver(randomFilters(2, 3, 9000, 9000, 51), b, 2);
  ASSERT_GE(convolver.partitionPlan().size(), 3u);
  AudioBuffer in = makeSilentBuffer(2, b, 48000.0);
  for (std::size_t n = 0; n < b; ++n) in.channels[0][n] = std::sin(0.1 * n);
  AudioBuffer out;
  convolver.process(in, out);  // shapes `out` once
  convolver.setFilters(randomFilters(2, 3, 8000, 9000, 52));
  convolver.setFilters(randomFilters(2, 3, 7000, 9000, 53));  // waits for the first fade
  const long before = g_allocations.load();
  // Several periods of the largest level, through both fades.
  for (int k = 0; k < 600; ++k) convolver.process(in, out);
  convolver.reset();
  for (int k = 0; k < 100; ++k) convolver.process(in, out);
  EXPECT_EQ(g_allocations.load(), before);
}

TEST(PartitionedConvolver, NonUniformResetForgetsTheInput) {
  const std::size_t b = 64;
  const auto filters = randomFilters(1, 2, 5000, 5000, 61);
  PartitionedConvolver convolver(filters, b);
  const auto inputs = noiseInputs(1, 50, b, 80);
  stream(convolver, Channels(1, std::vector<float>(inputs[0].begin(), inputs[0].begin() + 77 * b)));
  convolver.reset();
  const auto out = stream(convolver, inputs);
  EXPECT_LT(errorDb(out, offline(filters, inputs), 0, inputs.front().size()), -100.0);
}

TEST(PartitionedConvolver, FiltersPreparedOnAnotherThreadSwapInAsTheMatrixDoes) {
  // The transforms run on a second thread while the first keeps streaming; swapped in at
  // the same block, the prepared matrix gives the output of setFilters(matrix), sample
  // for sample, before, during and after the fade.
  const std::size_t b = 64;
  const auto old_filters = randomFilters(2, 2, 6000, 6000, 71);
  const auto new_filters = randomFilters(2, 2, 5000, 6000, 72);
  const auto inputs = noiseInputs(2, 240, b, 0);
  const auto section = [&](std::size_t from_block, std::size_t to_block) {
    Channels part(2);
    for (std::size_t i = 0; i < 2; ++i) {
      part[i].assign(inputs[i].begin() + from_block * b, inputs[i].begin() + to_block * b);
    }
    return part;
  };
  PartitionedConvolver direct(old_filters, b, 3), prepared(old_filters, b, 3);
  ASSERT_GE(prepared.partitionPlan().size(), 3u);
  Channels want = stream(direct, section(0, 131));
  direct.setFilters(new_filters);
  const auto want_rest = stream(direct, section(131, 240));

  std::shared_ptr<const PreparedFilters> ready;
  std::thread worker([&] { ready = PartitionedConvolver::prepare(new_filters, prepared.partitionPlan(), b); });
  Channels got = stream(prepared, section(0, 131));
  worker.join();
  prepared.setFilters(ready);
  const auto got_rest = stream(prepared, section(131, 240));
  for (std::size_t o = 0; o < 2; ++o) {
    want[o].insert(want[o].end(), want_rest[o].begin(), want_rest[o].end());
    got[o].insert(got[o].end(), got_rest[o].begin(), got_rest[o].end());
    ASSERT_EQ(got[o], want[o]) << "output " << o;
  }
  // One prepared matrix serves any convolver of its plan, from its first block.
  PartitionedConvolver from_prepared(ready, 1);
  EXPECT_LT(errorDb(stream(from_prepared, inputs), offline(new_filters, inputs), 0, inputs.front().size()), -100.0);
}

TEST(PartitionedConvolver, PreparedFiltersOfAnotherPlanAreRefused) {
  const std::size_t b = 64;
  const auto filters = randomFilters(1, 2, 6000, 6000, 81);
  PartitionedConvolver convolver(filters, b);
  const auto uniform = planPartitions(6000, b, b, 1, 2);
  expectInputError([&] { convolver.setFilters(PartitionedConvolver::prepare(filters, uniform, b)); },
                   {"another partition plan"});
  expectInputError([&] { convolver.setFilters(PartitionedConvolver::prepare(filters, convolver.partitionPlan(), 2 * b)); },
                   {"block size"});
  expectInputError(
      [&] { convolver.setFilters(PartitionedConvolver::prepare(randomFilters(2, 2, 100, 100, 82), convolver.partitionPlan(), b)); },
      {"2 inputs x 2 outputs", "1 x 2"});
  expectInputError([&] { convolver.setFilters(std::shared_ptr<const PreparedFilters>()); }, {"no prepared filters"});
  expectInputError([&] { PartitionedConvolver(std::shared_ptr<const PreparedFilters>(), 1); }, {"no prepared filters"});
  expectInputError([&] { PartitionedConvolver::prepare(filters, {}, b); }, {"partition plan"});
  expectInputError([&] { PartitionedConvolver::prepare(FilterMatrix{}, convolver.partitionPlan(), b); }, {"no input channels"});
  // The convolver keeps its filters.
  const auto inputs = noiseInputs(1, 120, b, 0);
  EXPECT_LT(errorDb(stream(convolver, inputs), offline(filters, inputs), 0, inputs.front().size()), -100.0);
}
