// What it costs to run simulations elsewhere (simulation_runner.h): the encoding of a job
// and of its result, and the five pairs of the sample-room diagnosis (bench_diagnosis's
// positions, 10 000 rays, first order, 1.5 s) simulated in this process on 2 threads
// against the same five in one or two worker processes of the tool, which give the same
// bits. On one 2-core machine two workers cannot be faster than this process: the
// benchmark measures the overhead (process start, encoding, the scene built again in
// each worker, the transfer), which is what a second machine's speed-up is net of.
// Run: scripts/bench, or this binary alone (about a minute).
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/simulation_runner.h"
#include "room_reverb/acoustics/simulation_wire.h"
#include "room_reverb/acoustics/triangle_mesh.h"
#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/evaluation/simulated_pairs.h"
#include "sample_room_pairs.h"

namespace {

using namespace room_reverb::core;

const std::string kSource = ROOM_REVERB_SOURCE_DIR;

const AcousticScene& cr2Scene() {
  static const AcousticScene scene(loadMesh(kSource + "/data/bras_cr2/geometry/cr2_scene9.ac", UpAxis::kY),
                                   MaterialLibrary::loadDefault());
  return scene;
}

const AcousticScene& sampleRoom() {
  static const AcousticScene scene =
      roomModelToScene(loadRoomModel(kSource + "/data/sample_room/visible.yaml"), MaterialLibrary::loadDefault());
  return scene;
}


SimulationSettings diagnosisSettings() {
  SimulationSettings s;
  s.rays.ray_count = 10000;
  s.rays.threads = 2;
  s.duration_s = 1.5;
  s.ambisonic_order = 1;
  return s;
}

// A CR2 job encoded, then split and its scene decoded (the BVH built) as a worker does.
void BM_Cr2JobEncodeDecode(benchmark::State& state) {
  SimulationRequest request;
  request.source_m = {0.931, -2.547, 0.723};
  request.listener_m = {-0.993, 1.426, 1.230};
  request.settings.rays.threads = 1;
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::vector<std::uint8_t> job = encodeJob(encodeScene(cr2Scene()), request);
    const JobParts parts = splitJob(job.data(), job.size());
    benchmark::DoNotOptimize(decodeScene(parts.scene, parts.scene_size));
    bytes = job.size();
  }
  state.counters["job_bytes"] = static_cast<double>(bytes);
  state.counters["triangles"] = static_cast<double>(cr2Scene().mesh().triangleCount());
}
BENCHMARK(BM_Cr2JobEncodeDecode)->Unit(benchmark::kMillisecond)->UseRealTime();

// A sample-room result (first order, 1.5 s) encoded and decoded.
void BM_ResultEncodeDecode(benchmark::State& state) {
  SimulationSettings s = diagnosisSettings();
  s.rays.ray_count = 2000;
  const MeasurementPair pair = room_reverb::bench::sampleRoomFivePairs().front();
  const SimulationResult result = simulateRoom(sampleRoom(), pair.source_m, pair.receiver_m, s);
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::vector<std::uint8_t> encoded = encodeResult(result);
    benchmark::DoNotOptimize(decodeResult(encoded.data(), encoded.size()));
    bytes = encoded.size();
  }
  state.counters["result_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_ResultEncodeDecode)->Unit(benchmark::kMillisecond)->UseRealTime();

// The five pairs: arg 0 in this process, N > 0 in N worker processes (started once,
// outside the timing, as in a diagnosis that runs tens of batches).
void BM_SampleRoomFivePairs(benchmark::State& state) {
  const std::vector<SimulationRequest> requests = pairRequests(room_reverb::bench::sampleRoomFivePairs(), diagnosisSettings());
  const int workers = static_cast<int>(state.range(0));
  std::unique_ptr<SimulationRunner> runner;
  if (workers > 0) {
    runner = std::make_unique<WorkerProcessSimulationRunner>(localWorkerCommands(workers, ROOM_REVERB_TOOL));
    runner->simulate(sampleRoom(), {requests.front()}, nullptr);  // the processes up
  } else {
    runner = std::make_unique<InProcessSimulationRunner>(2);
  }
  for (auto _ : state) benchmark::DoNotOptimize(runner->simulate(sampleRoom(), requests, nullptr));
}
BENCHMARK(BM_SampleRoomFivePairs)->ArgName("workers")->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
