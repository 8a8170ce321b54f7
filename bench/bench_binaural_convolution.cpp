// Speed of the binaural streaming path at 48 kHz in blocks of 256, for the two ways the
// renderer can be built:
//  - ambisonic: a mono source through a 1 x 16 matrix of 2 s third-order room responses,
//    rotated for the head, then a 16 x 2 matrix of short (256-tap) HRIR decoder filters;
//  - binaural room response: a mono source through a 1 x 2 matrix of 2 s BRIRs (no head
//    tracking);
// each stage alone and the ambisonic chain whole, plus the 16 x 2 matrix of 2 s filters
// (a binaural decoder of the whole room response), non-uniform and, for comparison,
// uniformly partitioned. Run: scripts/bench
//
// Each streaming benchmark runs 3 times and reports the median and the maximum of its
// counters over the runs:
//   rtf            seconds of audio streamed / CPU seconds spent: above 1 keeps up with
//                  real time on one core.
//   mean_block_us  mean thread CPU time of one block.
//   p999_block_us  the 99.9th percentile of the blocks' thread CPU times.
//   worst_block_us the longest block (thread CPU time, so time the thread spends
//                  preempted does not count, but cache misses caused by other processes
//                  do): what the audio callback must allow for.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/audio/partitioned_convolver.h"
#include "bench_clock.h"

namespace {

using room_reverb::bench::threadCpuSeconds;
using room_reverb::core::AudioBuffer;
using room_reverb::core::FilterMatrix;
using room_reverb::core::PartitionedConvolver;

constexpr double kRateHz = 48000.0;
constexpr std::size_t kBlock = 256;
constexpr std::size_t kRoomResponseTaps = static_cast<std::size_t>(2.0 * kRateHz);
constexpr std::size_t kDecoderTaps = 256;

// Exponentially decaying noise (T60 1 s), the shape of a room response.
FilterMatrix decayingNoiseFilters(std::size_t inputs, std::size_t outputs, std::size_t length) {
  std::mt19937 rng(1);
  std::normal_distribution<float> normal;
  const double delta = 6.0 * std::log(10.0) / kRateHz;
  FilterMatrix filters(inputs, std::vector<std::vector<float>>(outputs, std::vector<float>(length)));
  for (auto& row : filters) {
    for (auto& filter : row) {
      for (std::size_t n = 0; n < length; ++n) filter[n] = static_cast<float>(normal(rng) * std::exp(-0.5 * delta * n));
    }
  }
  return filters;
}

AudioBuffer noiseBlock(std::size_t channels) {
  AudioBuffer block = room_reverb::core::makeSilentBuffer(channels, kBlock, kRateHz);
  std::mt19937 rng(2);
  std::normal_distribution<float> normal;
  for (auto& channel : block.channels) {
    for (float& sample : channel) sample = normal(rng);
  }
  return block;
}

// Runs `block` once per iteration and sets the counters described above.
template <typename Block>
void streamBlocks(benchmark::State& state, Block block) {
  std::vector<double> spent_s;
  spent_s.reserve(static_cast<std::size_t>(state.max_iterations));
  for (auto _ : state) {
    const double start = threadCpuSeconds();
    block();
    spent_s.push_back(threadCpuSeconds() - start);
  }
  if (spent_s.empty()) return;
  double total_s = 0.0;
  for (double s : spent_s) total_s += s;
  std::sort(spent_s.begin(), spent_s.end());
  // kIsIterationInvariantRate divides by the CPU time of the run: audio s per CPU s.
  state.counters["rtf"] = benchmark::Counter(kBlock / kRateHz, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["mean_block_us"] = 1e6 * total_s / spent_s.size();
  state.counters["p999_block_us"] = 1e6 * spent_s[spent_s.size() * 999 / 1000];
  state.counters["worst_block_us"] = 1e6 * spent_s.back();
}

double maximum(const std::vector<double>& values) { return *std::max_element(values.begin(), values.end()); }

// Three runs, their median and maximum only.
void streamingRuns(benchmark::internal::Benchmark* benchmark) {
  benchmark->Repetitions(3)->ReportAggregatesOnly(true)->ComputeStatistics("max", maximum)->Unit(benchmark::kMicrosecond);
}

// One convolver, inputs x outputs filters of `taps`; range(0) is the largest partition
// size (kBlock gives the uniform convolver).
void convolve(benchmark::State& state, std::size_t inputs, std::size_t outputs, std::size_t taps) {
  PartitionedConvolver convolver(decayingNoiseFilters(inputs, outputs, taps), kBlock, 1,
                                 static_cast<std::size_t>(state.range(0)));
  const AudioBuffer input = noiseBlock(inputs);
  AudioBuffer output;
  streamBlocks(state, [&] {
    convolver.process(input, output);
    benchmark::DoNotOptimize(output.channels.front().data());
  });
  state.counters["partitions"] = static_cast<double>(convolver.partitionCount());
  state.counters["levels"] = static_cast<double>(convolver.partitionPlan().size());
}

void BM_MonoToThirdOrderRoomResponse(benchmark::State& state) { convolve(state, 1, 16, kRoomResponseTaps); }
void BM_ThirdOrderHrirDecoder(benchmark::State& state) { convolve(state, 16, 2, kDecoderTaps); }
void BM_MonoToBinauralRoomResponse(benchmark::State& state) { convolve(state, 1, 2, kRoomResponseTaps); }
void BM_ThirdOrderToBinauralRoomResponse(benchmark::State& state) { convolve(state, 16, 2, kRoomResponseTaps); }

constexpr auto kMaxPartition = static_cast<std::int64_t>(PartitionedConvolver::kDefaultMaxPartitionSize);
BENCHMARK(BM_MonoToThirdOrderRoomResponse)->Arg(kMaxPartition)->Apply(streamingRuns);
BENCHMARK(BM_ThirdOrderHrirDecoder)->Arg(kMaxPartition)->Apply(streamingRuns);
BENCHMARK(BM_MonoToBinauralRoomResponse)->Arg(kMaxPartition)->Apply(streamingRuns);
// kBlock: the uniformly partitioned convolver the renderer started with, for comparison.
BENCHMARK(BM_ThirdOrderToBinauralRoomResponse)->Arg(kMaxPartition)->Arg(kBlock)->Apply(streamingRuns);

// The ambisonic renderer's whole block: room response, head rotation (a new orientation
// every block, as a tracker delivers them), decoder.
void BM_AmbisonicBinauralChain(benchmark::State& state) {
  PartitionedConvolver room(decayingNoiseFilters(1, 16, kRoomResponseTaps), kBlock);
  PartitionedConvolver decoder(decayingNoiseFilters(16, 2, kDecoderTaps), kBlock);
  const AudioBuffer source = noiseBlock(1);
  AudioBuffer field;
  AudioBuffer ears;
  double yaw = 0.0;
  streamBlocks(state, [&] {
    room.process(source, field);
    yaw += 0.01;
    const Eigen::Quaterniond head(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    room_reverb::core::rotateAmbisonicBuffer(field, room_reverb::core::headTrackingRotation(head, 3));
    decoder.process(field, ears);
    benchmark::DoNotOptimize(ears.channels.front().data());
  });
}
BENCHMARK(BM_AmbisonicBinauralChain)->Apply(streamingRuns);

// A filter swap of the long convolution: transforming 16 x 2 s of filters and computing
// their share of the output already in flight. Outside the audio callback, or its cost.
void BM_SwapThirdOrderRoomResponse(benchmark::State& state) {
  PartitionedConvolver convolver(decayingNoiseFilters(1, 16, kRoomResponseTaps), kBlock);
  const FilterMatrix next = decayingNoiseFilters(1, 16, kRoomResponseTaps);
  const AudioBuffer source = noiseBlock(1);
  AudioBuffer field;
  for (int k = 0; k < 100; ++k) convolver.process(source, field);
  for (auto _ : state) convolver.setFilters(next);
}
BENCHMARK(BM_SwapThirdOrderRoomResponse)->Unit(benchmark::kMillisecond);

// The same swap in two steps: prepare() (the transforms, off the audio thread) and
// setFilters() of the prepared matrix (the share of the output in flight, on it).
void BM_PrepareThirdOrderRoomResponse(benchmark::State& state) {
  const PartitionedConvolver convolver(decayingNoiseFilters(1, 16, kRoomResponseTaps), kBlock);
  const FilterMatrix next = decayingNoiseFilters(1, 16, kRoomResponseTaps);
  for (auto _ : state) benchmark::DoNotOptimize(PartitionedConvolver::prepare(next, convolver.partitionPlan(), kBlock));
}
BENCHMARK(BM_PrepareThirdOrderRoomResponse)->Unit(benchmark::kMillisecond);

void BM_SwapPreparedThirdOrderRoomResponse(benchmark::State& state) {
  PartitionedConvolver convolver(decayingNoiseFilters(1, 16, kRoomResponseTaps), kBlock);
  const auto next = PartitionedConvolver::prepare(decayingNoiseFilters(1, 16, kRoomResponseTaps), convolver.partitionPlan(), kBlock);
  const AudioBuffer source = noiseBlock(1);
  AudioBuffer field;
  for (int k = 0; k < 100; ++k) convolver.process(source, field);
  for (auto _ : state) convolver.setFilters(next);
}
BENCHMARK(BM_SwapPreparedThirdOrderRoomResponse)->Unit(benchmark::kMillisecond);

void BM_ThirdOrderRotationMatrix(benchmark::State& state) {
  // A different orientation each time, as a head tracker delivers them.
  double yaw = 0.0;
  for (auto _ : state) {
    yaw += 0.01;
    const Eigen::Quaterniond head(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
    benchmark::DoNotOptimize(room_reverb::core::headTrackingRotation(head, 3));
  }
}
BENCHMARK(BM_ThirdOrderRotationMatrix)->Unit(benchmark::kMicrosecond);

void BM_RotateThirdOrderBlock(benchmark::State& state) {
  AudioBuffer block = room_reverb::core::makeSilentBuffer(16, kBlock, kRateHz);
  const Eigen::MatrixXd rotation =
      room_reverb::core::headTrackingRotation(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ())), 3);
  for (auto _ : state) {
    room_reverb::core::rotateAmbisonicBuffer(block, rotation);
    benchmark::DoNotOptimize(block.channels.front().data());
  }
}
BENCHMARK(BM_RotateThirdOrderBlock)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
