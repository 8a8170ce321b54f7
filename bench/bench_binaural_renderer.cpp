// CPU share of the binaural_renderer node's audio thread at 48 kHz: what one chunk of the
// node's default configuration costs (2 blocks of 256: a looped source, a 2 s third-order
// room response, a head orientation changing every chunk, the bundled KU100 MagLS decoder,
// interleaving into the published message's layout), over the chunk's 10.7 ms. The ROS
// side (serialising 1024 floats, the spinner) is measured live by the rostest
// (test/ros/test_binaural_renderer.cpp records render_cpu_share and process_cpu_share).
// Run: scripts/bench (all benchmarks) or .ws/devel/lib/room_reverb/bench_binaural_renderer
//   cpu_share  thread CPU time per chunk / chunk duration: the share of one core.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "room_reverb/binaural/binaural_stream.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/binaural/source_feed.h"
#include "bench_clock.h"

namespace {

using room_reverb::bench::threadCpuSeconds;
using namespace room_reverb::core;

constexpr std::size_t kBlock = 256;
constexpr std::size_t kChunkBlocks = 2;

AudioBuffer decayingNoise(std::size_t channels, double seconds, std::uint32_t seed) {
  const auto frames = static_cast<std::size_t>(seconds * kInternalSampleRateHz);
  AudioBuffer b = makeSilentBuffer(channels, frames, kInternalSampleRateHz);
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal;
  const double delta = 6.0 * std::log(10.0) / kInternalSampleRateHz;  // T60 1 s
  for (auto& c : b.channels) {
    for (std::size_t n = 0; n < frames; ++n) c[n] = static_cast<float>(0.1 * normal(rng) * std::exp(-0.5 * delta * n));
  }
  return b;
}

void BM_RendererChunk(benchmark::State& state) {
  const HrtfSet hrtf = HrtfSet::loadSofa(HrtfSet::defaultSofaPath());
  BinauralStream stream(makeBinauralDecoder(hrtf, 3));
  stream.setRoom(decayingNoise(16, 2.0, 1));
  LoopedSource source(decayingNoise(1, 3.0, 2));
  std::vector<float> block(kBlock), left(kBlock * kChunkBlocks), right(kBlock * kChunkBlocks);
  std::vector<float> message(2 * kBlock * kChunkBlocks);
  double yaw = 0.0, spent = 0.0;
  for (auto _ : state) {
    const double start = threadCpuSeconds();
    yaw += 0.002;
    stream.setHeadOrientation(Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())));
    for (std::size_t b = 0; b < kChunkBlocks; ++b) {
      source.read(block.data(), kBlock);
      stream.process(block.data(), left.data() + b * kBlock, right.data() + b * kBlock);
    }
    for (std::size_t n = 0; n < left.size(); ++n) {
      message[2 * n] = left[n];
      message[2 * n + 1] = right[n];
    }
    benchmark::DoNotOptimize(message.data());
    spent += threadCpuSeconds() - start;
  }
  const double chunk_s = static_cast<double>(kBlock * kChunkBlocks) / kInternalSampleRateHz;
  state.counters["cpu_share"] = spent / (static_cast<double>(state.iterations()) * chunk_s);
}
BENCHMARK(BM_RendererChunk)->Unit(benchmark::kMicrosecond)->Repetitions(3)->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
