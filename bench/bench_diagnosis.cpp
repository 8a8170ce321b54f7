// Speed of the diagnosis (target: one room with five measured RIRs diagnosed in
// under 2 minutes on 2 cores), at the diagnose tool's defaults (10 000 rays, image-source
// order 3, the whole catalogue, at most three causes). The room is the bundled sample
// room: the "measurement" is five B-format responses simulated from its acoustic twin
// (data/sample_room/acoustic.yaml: parquet floor, a hidden cabinet, air at 24 degC / 35 %),
// the model is what the cameras see (visible.yaml). The label names what was found, so a
// run also shows whether five pairs tell the room's three differences apart (one pair, as
// in scripts/demo, cannot: docs/diagnosis.md). The second case gives the ray tracer four
// times the rays and its detection sphere four times the crossings (the sphere the first
// case gets, where the listener's clearance allows), to see whether the rays then lower the
// noise: they do not (about 4 times the runtime; docs/validation/diagnosis.md). The third
// hands the simulations to two worker processes of the tool (simulation_runner.h): the
// same diagnosis to the bit, and on one 2-core machine what that costs.
// Run: scripts/bench, or .ws/devel/lib/room_reverb/bench_diagnosis.
#include <benchmark/benchmark.h>

#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_simulation.h"
#include "sample_room_pairs.h"
#include "room_reverb/acoustics/simulation_runner.h"
#include "room_reverb/diagnosis/diagnosis.h"
#include "room_reverb/diagnosis/diagnosis_setup.h"

namespace {

using namespace room_reverb::core;

const std::string kSampleRoom = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/sample_room/";


// The five "measured" responses: more rays and other seeds than the diagnosis uses, so
// the measurement's ray noise is its own.
const MeasuredEvidence& measuredEvidence() {
  static const MeasuredEvidence evidence = [] {
    const MaterialLibrary library = MaterialLibrary::loadDefault();
    const RoomUnderTest truth = RoomUnderTest::fromRoomModel(loadRoomModel(kSampleRoom + "acoustic.yaml"), library);
    const AcousticScene scene = truth.scene({});
    SimulationSettings s;
    s.duration_s = 1.5;
    s.ambisonic_order = 1;
    s.air = truth.air();
    s.rays.ray_count = 40000;
    MeasuredEvidence e;
    e.positions = room_reverb::bench::sampleRoomFivePairs();
    for (std::size_t i = 0; i < e.positions.size(); ++i) {
      s.rays.seed = 9000 + static_cast<std::uint32_t>(i);
      const SimulationResult r = simulateRoom(scene, e.positions[i].source_m, e.positions[i].receiver_m, s);
      e.rirs.push_back(analysePair(e.positions[i], r.impulse_response));
    }
    return e;
  }();
  return evidence;
}

void BM_DiagnoseSampleRoomFivePairs(benchmark::State& state) {
  const MeasuredEvidence& evidence = measuredEvidence();
  const RoomUnderTest model =
      RoomUnderTest::fromRoomModel(loadRoomModel(kSampleRoom + "visible.yaml"), MaterialLibrary::loadDefault());
  DiagnosisOptions options;  // the diagnose tool's defaults but for rays and crossings
  options.evaluation.simulation.rays.ray_count = static_cast<std::size_t>(state.range(0));
  options.evaluation.simulation.rays.crossings_per_ms = static_cast<double>(state.range(1));
  options.evaluation.simulation.image_source_order = 3;
  options.evaluation.simulation.rays.seed = 1;
  options.evaluation.simulation.duration_s = diagnosisDurationS(evidence);
  if (state.range(2) > 0) {
    options.evaluation.runner = std::make_shared<WorkerProcessSimulationRunner>(
        localWorkerCommands(static_cast<int>(state.range(2)), ROOM_REVERB_TOOL));
  }
  Diagnosis last;
  for (auto _ : state) {
    last = diagnose(model, evidence, options);
    benchmark::DoNotOptimize(last.causes.size());
  }
  state.counters["simulations"] = last.simulations;
  state.counters["baseline_jnd"] = last.baseline_error_jnd;
  state.counters["noise_jnd"] = last.noise_jnd;
  state.counters["threshold_jnd"] = last.threshold_jnd;
  state.counters["heldout_jnd"] = last.baseline_heldout_jnd;
  state.counters["after_jnd"] = last.after.error_jnd;
  std::ostringstream named;
  for (const NamedCause& c : last.causes) {
    named << (named.tellp() > 0 ? ", " : "") << c.cause << (c.target.empty() ? "" : "(" + c.target + ")") << " +"
          << c.heldoutGainJnd();
  }
  state.SetLabel(last.causes.empty() ? "no cause named" : named.str());
}
// One diagnosis takes about a minute: one iteration per repetition.
BENCHMARK(BM_DiagnoseSampleRoomFivePairs)
    ->ArgNames({"rays", "crossings_per_ms", "workers"})
    ->Args({10000, 300, 0})
    ->Args({40000, 1200, 0})
    ->Args({10000, 300, 2})
    ->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
