// Simulations handed to other processes: the encoding of a job and of its result, the
// worker processes, and that the comparison and the diagnosis's evaluations come out the
// same to the bit wherever their simulations ran.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <sys/wait.h>
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/simulation_runner.h"
#include "room_reverb/acoustics/simulation_wire.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/worker_process.h"
#include "room_reverb/diagnosis/diagnosis.h"
#include "room_reverb/diagnosis/model_evaluation.h"
#include "room_reverb/evaluation/measurement_comparison.h"
#include "room_reverb/evaluation/simulated_pairs.h"
#include "planted_room.h"
#include "test_rooms.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

const std::string kWorker = std::string(ROOM_REVERB_TOOL) + " simulate-worker";

// The studio with two objects, one flush against a wall and the floor, and a material
// override: everything a scene resolves must cross.
AcousticScene studioScene() {
  RoomModel room = parseRoomModel(kStudioRoomYaml);
  room.objects.push_back(woodCuboid("cabinet", {0.3, 2.0, 0.5}, {0.6, 1.2, 1.0}));
  room.objects.push_back(woodCuboid("table", {3.0, 2.2, 0.37}, {1.4, 0.8, 0.74}, 0.4));
  MaterialOverrides overrides;
  overrides.scattering["wood_panel"] = OctaveBandValues{0.1, 0.1, 0.2, 0.3, 0.4, 0.5, 0.5, 0.6, 0.6};
  return roomModelToScene(room, MaterialLibrary::loadDefault(), overrides);
}

// Settings far from the defaults in every field the encoding carries.
SimulationRequest unusualRequest() {
  SimulationRequest r;
  r.source_m = {1.2, 1.0, 1.4};
  r.listener_m = {3.6, 2.8, 1.3};
  SimulationSettings& s = r.settings;
  s.image_source_order = 2;
  s.duration_s = 0.4;
  s.ambisonic_order = 1;
  s.air.temperature_c = 24.0;
  s.air.humidity_percent = 35.0;
  s.air.pressure_kpa = 98.0;
  s.directivity.omni_fraction = 0.5;
  s.directivity.axis = Eigen::Vector3d(0.0, 1.0, 0.0);
  s.rays.ray_count = 1500;
  s.rays.crossings_per_ms = 200.0;
  s.rays.roulette_db = -50.0;
  s.rays.continuation.bend_db = 0.7;
  s.diffraction_scattering = true;  // not the default, so a lost flag shows
  std::array<double, kLaunchCells> weights{};
  for (int c = 0; c < kLaunchCells; ++c) weights[static_cast<std::size_t>(c)] = 1.0 + c % 7;
  s.rays.launch_density = std::make_shared<LaunchDensity>(weights);
  s.rays.record_launch_cells = true;
  s.fast_rays.late_launch_mixture = 0.3;
  s.rays.seed = 42;
  s.rays.threads = 2;
  s.fast_ray_count = 700;
  return r;
}

std::vector<std::uint8_t> bytesOf(const SimulationResult& r) { return encodeResult(r); }

TEST(SimulationWire, ADecodedJobSimulatesToTheSameBits) {
  const AcousticScene scene = studioScene();
  const SimulationRequest request = unusualRequest();
  const std::vector<std::uint8_t> scene_bytes = encodeScene(scene);
  const std::unique_ptr<AcousticScene> decoded = decodeScene(scene_bytes.data(), scene_bytes.size());
  EXPECT_EQ(encodeScene(*decoded), scene_bytes);
  EXPECT_DOUBLE_EQ(decoded->volumeM3(), scene.volumeM3());
  ASSERT_NE(decoded->roomShape(), nullptr);
  EXPECT_EQ(decoded->roomShape()->objects.size(), 2u);
  EXPECT_EQ(decoded->roomShape()->objects[0].label, "cabinet");
  EXPECT_EQ(decoded->isInside({0.3, 2.0, 0.5}), false);  // inside the cabinet

  const std::vector<std::uint8_t> request_bytes = encodeRequest(request);
  EXPECT_EQ(encodeRequest(decodeRequest(request_bytes.data(), request_bytes.size())), request_bytes);
  EXPECT_TRUE(decodeRequest(request_bytes.data(), request_bytes.size()).settings.diffraction_scattering);
  const SimulationSettings settings_back = decodeRequest(request_bytes.data(), request_bytes.size()).settings;
  ASSERT_TRUE(settings_back.rays.launch_density);
  EXPECT_EQ(settings_back.rays.launch_density->probabilities(), request.settings.rays.launch_density->probabilities());
  EXPECT_DOUBLE_EQ(settings_back.fast_rays.late_launch_mixture, 0.3);

  const SimulationResult here = simulateRoom(scene, request.source_m, request.listener_m, request.settings);
  SimulationJobExecutor executor;
  const std::vector<std::uint8_t> job = encodeJob(scene_bytes, request);
  const std::vector<std::uint8_t> there = executor.run(job.data(), job.size());
  EXPECT_EQ(there, bytesOf(here));
  const SimulationResult back = decodeResult(there.data(), there.size());
  ASSERT_EQ(back.impulse_response.channels.size(), 4u);
  EXPECT_EQ(back.impulse_response.channels[2], here.impulse_response.channels[2]);
  ASSERT_EQ(back.paths.size(), here.paths.size());
  EXPECT_EQ(back.paths.back().triangles, here.paths.back().triangles);
  EXPECT_EQ(back.stats.reflections, here.stats.reflections);
  EXPECT_DOUBLE_EQ(back.late.energy(100, 4), here.late.energy(100, 4));
  EXPECT_DOUBLE_EQ(back.late.flux(100, 4).y(), here.late.flux(100, 4).y());

  // Every mode and a mesh scene with no room shape (closed by the flag alone).
  for (SimulationMode mode : {SimulationMode::kFast, SimulationMode::kEyring}) {
    SimulationRequest r = request;
    r.settings.mode = mode;
    const std::vector<std::uint8_t> j = encodeJob(scene_bytes, r);
    EXPECT_EQ(executor.run(j.data(), j.size()), bytesOf(simulateRoom(scene, r.source_m, r.listener_m, r.settings)))
        << toString(mode);
  }
  const AcousticScene mesh_scene(scene.mesh(), MaterialLibrary::loadDefault(), {}, true);
  const std::vector<std::uint8_t> mesh_bytes = encodeScene(mesh_scene);
  const std::unique_ptr<AcousticScene> mesh_back = decodeScene(mesh_bytes.data(), mesh_bytes.size());
  EXPECT_EQ(mesh_back->roomShape(), nullptr);
  EXPECT_TRUE(mesh_back->closed());
  EXPECT_NEAR(mesh_back->volumeM3(), mesh_scene.volumeM3(), 1e-12);
}

TEST(SimulationWire, BrokenBytesAreAnInputErrorNeverACrash) {
  const AcousticScene scene = studioScene();
  SimulationRequest request = unusualRequest();
  const std::vector<std::uint8_t> job = encodeJob(encodeScene(scene), request);
  // Cut anywhere (every 97th byte, and the last one), the job is refused with a reason.
  SimulationJobExecutor executor;
  std::vector<std::size_t> cuts;
  for (std::size_t cut = 0; cut < job.size(); cut += 97) cuts.push_back(cut);
  cuts.push_back(job.size() - 1);
  for (std::size_t cut : cuts) {
    try {
      executor.run(job.data(), cut);
      ADD_FAILURE() << "a job cut at byte " << cut << " was run";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("simulation"), std::string::npos) << e.what();
    }
  }
  // Another version's marker; a count that claims more than there is; a bad flag.
  std::vector<std::uint8_t> bad = job;
  bad[0] ^= 0x01;
  EXPECT_THROW(executor.run(bad.data(), bad.size()), InputError);
  bad = job;
  const std::uint64_t huge = std::uint64_t{1} << 40;
  std::memcpy(bad.data() + 4, &huge, 8);
  EXPECT_THROW(executor.run(bad.data(), bad.size()), InputError);
  // A thread count of 0 would make the result depend on the machine that runs it.
  request.settings.rays.threads = 0;
  const std::vector<std::uint8_t> unfixed = encodeJob(encodeScene(scene), request);
  try {
    executor.run(unfixed.data(), unfixed.size());
    ADD_FAILURE() << "a job without a fixed thread count was run";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("thread count must be fixed"), std::string::npos) << e.what();
  }
  // A material coefficient outside [0, 1] is refused as the scene's own error.
  const std::vector<std::uint8_t> scene_bytes = encodeScene(scene);
  std::vector<std::uint8_t> scene_bad = scene_bytes;
  // The first absorption value of the first material, found by its name's bytes.
  const std::string first = scene.mesh().material_names.front();
  auto at = std::search(scene_bad.begin(), scene_bad.end(), first.begin(), first.end());
  ASSERT_NE(at, scene_bad.end());
  const double two = 2.0;
  std::memcpy(&*(at + static_cast<std::ptrdiff_t>(first.size())), &two, 8);
  EXPECT_THROW(decodeScene(scene_bad.data(), scene_bad.size()), InputError);
}

std::vector<SimulationRequest> threeRequests() {
  std::vector<SimulationRequest> requests(3, unusualRequest());
  requests[1].listener_m = {2.0, 3.0, 1.5};
  requests[1].settings.rays.seed = 7;
  requests[1].settings.rays.threads = 1;
  requests[2].source_m = {4.0, 1.1, 1.6};
  requests[2].settings.mode = SimulationMode::kFast;
  return requests;
}

TEST(WorkerProcessSimulationRunner, TwoWorkersGiveWhatThisProcessGives) {
  const AcousticScene scene = studioScene();
  const std::vector<SimulationRequest> requests = threeRequests();
  const std::vector<SimulationResult> here = InProcessSimulationRunner(2).simulate(scene, requests, nullptr);
  WorkerProcessSimulationRunner workers({kWorker, kWorker});
  EXPECT_EQ(workers.description(), "2 worker processes");
  std::vector<double> times;
  for (int batch = 0; batch < 2; ++batch) {  // the workers stay up between batches
    const std::vector<SimulationResult> there = workers.simulate(scene, requests, &times);
    ASSERT_EQ(there.size(), here.size());
    for (std::size_t i = 0; i < here.size(); ++i) EXPECT_EQ(bytesOf(there[i]), bytesOf(here[i])) << "request " << i;
    ASSERT_EQ(times.size(), 3u);
    for (double t : times) EXPECT_GT(t, 0.0);
  }
}

TEST(WorkerProcessSimulationRunner, AWrongRequestIsTheCallersInputErrorAndTheWorkersCarryOn) {
  const AcousticScene scene = studioScene();
  std::vector<SimulationRequest> requests = threeRequests();
  requests[1].listener_m = {0.3, 2.0, 0.5};  // inside the cabinet
  WorkerProcessSimulationRunner workers({kWorker});
  try {
    workers.simulate(scene, requests, nullptr);
    ADD_FAILURE() << "a listener inside an object was simulated";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cabinet"), std::string::npos) << e.what();
  }
  requests[1] = requests[0];
  EXPECT_EQ(workers.simulate(scene, requests, nullptr).size(), 3u);
}

TEST(WorkerProcessSimulationRunner, AWorkerThatFailsIsNamedWithHowItEnded) {
  const AcousticScene scene = studioScene();
  const std::vector<SimulationRequest> requests = threeRequests();
  for (const auto& [command, expected] : std::vector<std::pair<std::string, std::string>>{
           {"exit 3", "exited with status 3"},
           {"head -c 100 >/dev/null; exit 0", "exited with status 0"},
           {"echo this-is-not-a-frame; exec cat >/dev/null", "not a stream of room_reverb frames"},
           {"/no/such/room_reverb simulate-worker", "exited with status 127"}}) {
    WorkerProcessSimulationRunner workers({command});
    try {
      workers.simulate(scene, requests, nullptr);
      ADD_FAILURE() << command << ": no error";
    } catch (const InputError& e) {
      ADD_FAILURE() << command << ": the caller's input blamed: " << e.what();
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(expected), std::string::npos) << command << ": " << what;
      EXPECT_NE(what.find(command), std::string::npos) << what;
    }
  }
  // One good worker beside a dead one: the failure is still reported, not hidden.
  WorkerProcessSimulationRunner mixed({kWorker, "exit 1"});
  EXPECT_THROW(mixed.simulate(scene, requests, nullptr), std::runtime_error);
}

TEST(WorkerProcessSimulationRunner, AWorkerRefusesInputThatIsNotAJobStream) {
  // As a user who runs it by hand would see it: exit 2 and one line.
  const int status = std::system((std::string("echo hello | ") + kWorker + " >/dev/null 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_EQ(WEXITSTATUS(std::system((std::string(": | ") + kWorker).c_str())), 0);
}

TEST(WorkerProcessSimulationRunner, TheDiagnosisEvaluatesTheSameOnWorkers) {
  const PlantedCase c = plantedCase("surface_absorption", 12);
  const RoomUnderTest room = RoomUnderTest::fromRoomModel(c.room, c.library);
  EvaluationSettings settings = testDiagnosisOptions().evaluation;
  settings.simulation.rays.ray_count = 1500;
  settings.simulation.rays.threads = 2;
  const Evaluation here = ModelEvaluator(room, c.evidence, settings).evaluate(c.planted, 1);
  settings.runner = std::make_shared<WorkerProcessSimulationRunner>(std::vector<std::string>{kWorker, kWorker});
  const Evaluation there = ModelEvaluator(room, c.evidence, settings).evaluate(c.planted, 1);
  ASSERT_TRUE(here.valid) << here.reason;
  ASSERT_TRUE(there.valid) << there.reason;
  EXPECT_EQ(there.error_jnd, here.error_jnd);
  EXPECT_EQ(there.heldout_error_jnd, here.heldout_error_jnd);
  ASSERT_EQ(there.terms.size(), here.terms.size());
  for (std::size_t i = 0; i < here.terms.size(); ++i) EXPECT_EQ(there.terms[i].error_jnd, here.terms[i].error_jnd) << i;
  for (std::size_t i = 0; i < here.predictions.size(); ++i) {
    EXPECT_EQ(there.predictions[i].simulated_omni, here.predictions[i].simulated_omni) << i;
    EXPECT_EQ(there.predictions[i].seed, here.predictions[i].seed) << i;
  }
  // And the comparison of the same measurement.
  const AcousticScene scene = room.scene({});
  SimulationSettings sim = settings.simulation;
  const MeasurementComparison a = compareMeasurement(scene, c.evidence, sim);
  const MeasurementComparison b = compareMeasurement(scene, c.evidence, sim, {}, settings.runner.get());
  ASSERT_EQ(a.pairs.size(), b.pairs.size());
  for (std::size_t i = 0; i < a.pairs.size(); ++i) EXPECT_EQ(a.pairs[i].simulated_omni, b.pairs[i].simulated_omni) << i;
  EXPECT_EQ(comparisonReportMarkdown(a), comparisonReportMarkdown(b));
}

TEST(WorkerProcessSimulationRunner, ADiagnosisOnWorkersNamesWhatThisProcessNames) {
  // The candidates of a fit go to the workers together (the surface probes and first
  // steps, the humidity grid, the noise seeds): the diagnosis must not change by a bit.
  const PlantedCase c = plantedCase("surface_absorption", 12);
  const RoomUnderTest room = RoomUnderTest::fromRoomModel(c.room, c.library);
  DiagnosisOptions options = testDiagnosisOptions();
  options.causes = {"surface_absorption", "air_absorption"};
  options.max_causes = 1;
  options.noise_seeds = 2;
  options.evaluation.simulation.rays.ray_count = 1000;
  const Diagnosis here = diagnose(room, c.evidence, options);
  options.evaluation.runner = std::make_shared<WorkerProcessSimulationRunner>(std::vector<std::string>{kWorker, kWorker});
  const Diagnosis there = diagnose(room, c.evidence, options);
  EXPECT_EQ(there.simulations, here.simulations);
  EXPECT_EQ(there.baseline_error_jnd, here.baseline_error_jnd);
  EXPECT_EQ(there.noise_jnd, here.noise_jnd);
  ASSERT_EQ(there.trials.size(), here.trials.size());
  for (std::size_t i = 0; i < here.trials.size(); ++i) {
    EXPECT_EQ(there.trials[i].target, here.trials[i].target) << here.trials[i].cause;
    EXPECT_EQ(there.trials[i].heldout_gain_jnd, here.trials[i].heldout_gain_jnd) << here.trials[i].cause;
    EXPECT_EQ(there.trials[i].note, here.trials[i].note) << here.trials[i].cause;
  }
  ASSERT_EQ(there.causes.size(), here.causes.size());
  for (std::size_t i = 0; i < here.causes.size(); ++i) {
    EXPECT_EQ(there.causes[i].cause, here.causes[i].cause);
    EXPECT_EQ(there.causes[i].heldout_after_jnd, here.causes[i].heldout_after_jnd);
  }
}

TEST(ParallelRounds, APairsThreadCountDependsOnlyOnItsPlaceInTheRounds) {
  // Five pairs on two threads: two full rounds of one thread each, then one pair on two.
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(roundThreads(5, 2, i), 1) << i;
  EXPECT_EQ(roundThreads(5, 2, 4), 2);
  const std::vector<MeasurementPair> pairs(5);
  SimulationSettings s;
  s.rays.seed = 10;
  s.rays.threads = 2;
  const std::vector<SimulationRequest> requests = pairRequests(pairs, s);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(requests[i].settings.rays.seed, 10u + i);
    EXPECT_EQ(requests[i].settings.rays.threads, roundThreads(5, 2, i));
  }
}

}  // namespace
}  // namespace room_reverb::test
