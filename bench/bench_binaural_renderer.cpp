// CPU share of the binaural_renderer node's audio thread at 48 kHz: what one chunk of the
// node's default configuration costs (2 blocks of 256: a looped source, a 2 s third-order
// room response, a head orientation changing every chunk, the bundled KU100 MagLS decoder,
// interleaving into the published message's layout), over the chunk's 10.7 ms; and the
// same with a first-order room response, whose twelve missing channels cost nothing. The ROS
// side (serialising 1024 floats, the spinner) is measured live by the rostest
// (test/ros/test_binaural_renderer.cpp records render_cpu_share and process_cpu_share).
// BM_WalkingRendererChunk is the same with the listener walking (docs/six_dof.md): a
// room's direct sound and 24 early reflections as taps, their targets found once a chunk
// (tapTargetsAt: ListenerTranslation::arrivalsAt in a room model, at the chunk's end) and blended
// for each block, as the node does; its late part as the 2 s room response, silent before
// the first reflection as an RSAO's late part is. BM_MovingTapsBlock is the taps alone for one block,
// BM_ReflectionsAtPose one pose's move alone.
// Run: scripts/bench (all benchmarks) or .ws/devel/lib/room_reverb/bench_binaural_renderer
//   cpu_share  thread CPU time per chunk / chunk duration: the share of one core.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/simulated_walk.h"
#include "room_reverb/binaural/binaural_stream.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/binaural/reflection_tap_bank.h"
#include "room_reverb/binaural/source_feed.h"
#include "room_reverb/binaural/walk_render.h"
#include "room_reverb/rsao/listener_translation.h"
#include "room_reverb/rsao/lpc.h"
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

// Streams chunks of the node's layout for the benchmark's iterations, the head turning a
// little each chunk; `before_block(t)` runs before each block at stream time t (s).
// Records the audio thread's share of one core.
void streamChunks(benchmark::State& state, BinauralStream& stream, const std::function<void(double)>& before_block) {
  LoopedSource source(decayingNoise(1, 3.0, 2));
  std::vector<float> block(kBlock), left(kBlock * kChunkBlocks), right(kBlock * kChunkBlocks);
  std::vector<float> message(2 * kBlock * kChunkBlocks);
  double yaw = 0.0, spent = 0.0, t = 0.0;
  for (auto _ : state) {
    const double start = threadCpuSeconds();
    yaw += 0.002;
    stream.setHeadOrientation(Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())));
    for (std::size_t b = 0; b < kChunkBlocks; ++b) {
      t += static_cast<double>(kBlock) / kInternalSampleRateHz;
      if (before_block) before_block(t);
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

void BM_RendererChunk(benchmark::State& state) {
  const HrtfSet hrtf = HrtfSet::loadSofa(HrtfSet::defaultSofaPath());
  BinauralStream stream(makeBinauralDecoder(hrtf, 3));
  stream.setRoom(decayingNoise(static_cast<std::size_t>(state.range(0)), 2.0, 1));
  streamChunks(state, stream, {});
}
// Arg: the room response's channels, 16 (third order) or 4 (a measured first-order RIR).
BENCHMARK(BM_RendererChunk)->Arg(16)->Arg(4)->Unit(benchmark::kMicrosecond)->Repetitions(3)->ReportAggregatesOnly(true);

// The third-order room as a mixed-order one (binaural/late_order.h): all orders for the
// first 0.1 s, orders 0-1 after it.
void BM_MixedOrderRendererChunk(benchmark::State& state) {
  const HrtfSet hrtf = HrtfSet::loadSofa(HrtfSet::defaultSofaPath());
  BinauralStreamOptions options;
  options.mixed_order_late = true;
  options.full_order_s = 0.1;
  BinauralStream stream(makeBinauralDecoder(hrtf, 3), options);
  stream.setRoom(decayingNoise(16, 2.0, 1));
  streamChunks(state, stream, {});
}
BENCHMARK(BM_MixedOrderRendererChunk)->Unit(benchmark::kMicrosecond)->Repetitions(3)->ReportAggregatesOnly(true);

// A 9 x 7 x 3 m room with a table, its source 3 m from the microphone: the RSAO is the
// room's own image sources to second order (25 arrivals, each matched to its walls, so
// every pose checks every path), as an estimate with a room model gives, each with a
// spectral shape of the estimator's order (9: five sections), as estimated reflections have.
RoomModel roomWithATable() {
  RoomModel model;
  model.size_m = {9.0, 7.0, 3.0};
  for (const char* name : kRoomSurfaceNames) model.surfaces[name] = SurfaceAssignment{"plaster_smooth", 1.0};
  model.rig_position_m = {4.0, 3.5, 1.5};
  CuboidObject table;
  table.label = "table";
  table.material = "wood";
  table.center_m = {6.0, 1.5, 0.4};
  table.size_m = {1.6, 0.9, 0.8};
  model.objects.push_back(table);
  return model;
}

ListenerTranslation walkableRoom() {
  const RoomModel model = roomWithATable();
  const Eigen::Vector3d source(6.5, 5.0, 1.6);
  const AcousticScene scene = roomModelToScene(model, MaterialLibrary::loadDefault());
  ImageSourceOptions search;
  search.max_order = 2;
  Rsao rsao;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (const SpecularPath& path : computeImageSources(scene, source, model.rig_position_m, PropagationModel{}, search)) {
    EarlyReflection r;
    r.time_of_arrival_s = path.delay_s;
    r.level = std::abs(path.pressure_gain[4]);
    r.azimuth_rad = std::atan2(path.arrival_direction.y(), path.arrival_direction.x());
    r.elevation_rad = std::asin(path.arrival_direction.z());
    r.distance_m = 343.2 * path.delay_s;
    std::vector<double> segment(96);  // 2 ms of a low-passed noise, Hann-windowed
    double y = 0.0;
    for (std::size_t n = 0; n < segment.size(); ++n) {
      y = 0.6 * y + normal(rng);
      segment[n] = y * (0.5 - 0.5 * std::cos(2.0 * 3.141592653589793 * static_cast<double>(n) / 95.0));
    }
    const LpcModel shape = fitLpc(segment, kDefaultLpcOrder);
    r.lpc = shape.a;
    r.lpc_gain = shape.gain;
    r.sos = allPoleToSections(shape.a, shape.gain);
    rsao.reflections.push_back(r);
  }
  std::sort(rsao.reflections.begin(), rsao.reflections.end(),
            [](const EarlyReflection& x, const EarlyReflection& y) { return x.time_of_arrival_s < y.time_of_arrival_s; });
  ListenerTranslationOptions options;
  options.speed_of_sound_m_s = 343.2;  // the image sources'
  return ListenerTranslation(rsao, model.rig_position_m, model.rig_rotation, model, options);
}

Eigen::Vector3d walking(double t_s) {  // 1 m/s around a circle of 1.5 m about the microphone
  return Eigen::Vector3d(4.0 + 1.5 * std::cos(t_s / 1.5), 3.5 + 1.5 * std::sin(t_s / 1.5), 1.6);
}

void BM_WalkingRendererChunk(benchmark::State& state) {
  const HrtfSet hrtf = HrtfSet::loadSofa(HrtfSet::defaultSofaPath());
  BinauralStreamOptions stream_options;
  stream_options.mixed_order_late = state.range(1) != 0;
  BinauralStream stream(makeBinauralDecoder(hrtf, 3), stream_options);
  const ListenerTranslation translation = walkableRoom();
  // The late part as an RSAO's is (rsao_resynthesis.h): zero before its onset, the first
  // reflection (here 11 ms after the emission).
  AudioBuffer late = decayingNoise(static_cast<std::size_t>(state.range(0)), 2.0, 1);
  const auto onset = static_cast<std::size_t>(translation.reflectionsAtRig()[1].time_of_arrival_s * kInternalSampleRateHz);
  for (auto& channel : late.channels) std::fill_n(channel.begin(), onset, 0.0f);
  stream.setRoom(late);
  ReflectionTapBankOptions options;
  options.order = 3;
  options.block_size = kBlock;
  stream.setEarlyTaps(std::make_unique<ReflectionTapBank>(translation.reflectionsAtRig(), options));
  // As the node walks: the targets at the chunk's end once a chunk, blended per block.
  ChunkedTapTargets targets;
  targets.place(tapTargetsAt(translation, walking(0.0)));
  std::size_t block = 0;
  const double block_s = static_cast<double>(kBlock) / kInternalSampleRateHz;
  streamChunks(state, stream, [&](double t) {
    const std::size_t b = block++ % kChunkBlocks;
    if (b == 0) {
      if (block > 1) targets.endChunk();
      targets.beginChunk(tapTargetsAt(translation, walking(t + static_cast<double>(kChunkBlocks - 1) * block_s)),
                         kChunkBlocks);
    }
    stream.earlyTaps()->setTargets(targets.atBlock(b));
  });
  state.counters["taps"] = static_cast<double>(translation.anchors().size());
}
// Args: the late part's channels as above (the node's walkable RSAO rooms have a
// first-order late part, 4), and 1 for a mixed-order late part (~mixed_order_late: all
// orders for the first 0.1 s, orders 0-1 after it).
BENCHMARK(BM_WalkingRendererChunk)
    ->Args({16, 0})
    ->Args({4, 0})
    ->Args({16, 1})
    ->Unit(benchmark::kMicrosecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

// The taps alone: one block of the 24 walking taps (filters of order 9) into a third-order
// field, their targets moved by a few centimetres each block (setTargets included).
void BM_MovingTapsBlock(benchmark::State& state) {
  const ListenerTranslation translation = walkableRoom();
  ReflectionTapBankOptions options;
  options.order = 3;
  options.block_size = kBlock;
  ReflectionTapBank bank(translation.reflectionsAtRig(), options);
  std::vector<std::vector<TapTarget>> targets;
  for (int k = 0; k < 64; ++k) targets.push_back(tapTargetsAt(translation, walking(0.005 * k)));
  LoopedSource source(decayingNoise(1, 3.0, 2));
  std::vector<float> block(kBlock);
  std::vector<std::vector<float>> field(bank.channels(), std::vector<float>(kBlock));
  std::vector<float*> out;
  for (auto& c : field) out.push_back(c.data());
  std::size_t next = 0;
  for (auto _ : state) {
    bank.setTargets(targets[next++ % targets.size()]);
    source.read(block.data(), kBlock);
    bank.process(block.data(), out.data());
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_MovingTapsBlock)->Unit(benchmark::kMicrosecond)->Repetitions(3)->ReportAggregatesOnly(true);

void BM_ReflectionsAtPose(benchmark::State& state) {
  const ListenerTranslation translation = walkableRoom();
  double t = 0.0;
  for (auto _ : state) {
    t += 0.01;
    benchmark::DoNotOptimize(tapTargetsAt(translation, walking(t)).data());
  }
}
BENCHMARK(BM_ReflectionsAtPose)->Unit(benchmark::kMicrosecond)->Repetitions(3)->ReportAggregatesOnly(true);

// The simulated route walked: the same room (and table) simulated in eyring mode at the
// microphone, second-order image sources, third-order AmbiX, a 2 s late part.
SimulatedWalk simulatedRoom() {
  const RoomModel model = roomWithATable();
  SimulationSettings settings;
  settings.mode = SimulationMode::kEyring;
  settings.image_source_order = 2;
  settings.ambisonic_order = 3;
  return SimulatedWalk(roomModelToScene(model, MaterialLibrary::loadDefault()), Eigen::Vector3d(6.5, 5.0, 1.6),
                       model.rig_position_m, settings);
}

// The worker's job for one pose: image sources and their synthesis.
void BM_SimulatedEarlyAtPose(benchmark::State& state) {
  const SimulatedWalk walk = simulatedRoom();
  double t = 0.0, frames = 0.0;
  for (auto _ : state) {
    t += 0.01;
    const AudioBuffer early = walk.earlyAt(walking(t));
    frames = static_cast<double>(early.frameCount());
    benchmark::DoNotOptimize(early.channels.data());
  }
  state.counters["early_ms"] = 1000.0 * frames / kInternalSampleRateHz;
}
BENCHMARK(BM_SimulatedEarlyAtPose)->Unit(benchmark::kMillisecond)->Repetitions(3)->ReportAggregatesOnly(true);

// The audio thread's share walking the simulated route: the late part convolved, a new
// early part swapped in every Arg chunks (the worker's pace). The worker prepares each
// (prepareEarlyResponse: its transforms), as the node does; the audio thread swaps it in.
void BM_SimulatedWalkChunk(benchmark::State& state) {
  const HrtfSet hrtf = HrtfSet::loadSofa(HrtfSet::defaultSofaPath());
  BinauralStream stream(makeBinauralDecoder(hrtf, 3));
  const SimulatedWalk walk = simulatedRoom();
  stream.setRoom(walk.late());
  std::vector<PreparedResponse> early;  // made beforehand: the worker's, not the audio thread's
  for (int k = 0; k < 50; ++k) early.push_back(stream.prepareEarlyResponse(walk.earlyAt(walking(0.02 * k))));
  std::size_t block = 0, next = 0;
  const auto every = static_cast<std::size_t>(2 * state.range(0));
  streamChunks(state, stream, [&](double) {
    if (block++ % every == 0) stream.setEarlyResponse(early[next++ % early.size()]);
  });
}
BENCHMARK(BM_SimulatedWalkChunk)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->Repetitions(3)->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
