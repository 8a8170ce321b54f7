// room_reverb diagnose: what the simulation of a room gets wrong against a measurement,
// the causes, the corrected model and the gain on held-out evidence.
#include <iomanip>
#include <set>
#include <iostream>
#include <sstream>

#include "arguments.h"
#include "command.h"
#include "room_reverb/acoustics/triangle_mesh.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/common/error.h"
#include "room_reverb/diagnosis/diagnosis_output.h"
#include "room_reverb/diagnosis/diagnosis_setup.h"
#include "simulation_workers.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb diagnose --measured MEAS.yaml [--room ROOM.yaml | --mesh FILE [--y-up]]
                            --out DIR [options]

Simulates the room at every measured pair, compares with the measurement (RIR files:
T20, T30, EDT, C80, D50, DRR per octave and the early energy profile, per pair; or the
file's table of averaged parameters), then tries each cause of the catalogue (air_absorption,
surface_absorption, scattering, missing_reflector, geometry_scale, coupled_volume,
source_directivity, low_frequency_modes): fits its few parameters on part of the evidence and measures the gain
on the rest. Causes whose held-out gain stands clear of the simulation's own noise are named,
best first. Writes DIR/diagnosis.json, DIR/report.md, DIR/*.png and, for a room model,
DIR/extended_room.yaml (the corrected room).

  --measured FILE    measurements.yaml (DESIGN.md): pairs with RIR files, or a table
  --room, --mesh     the room to diagnose (default: the one the measurements file names)
  --y-up             the mesh has y up
  --out DIR          output directory
  --causes LIST      comma-separated cause ids to try (default: the eight of the
                     catalogue; diffraction_scattering, wave_low_band and
                     third_octave_bands, which fit nothing, are tried only when
                     named here)
  --max-causes N     at most N causes (default 3)
  --rays N           rays per simulation (default 10000)
  --order N          image-source order (default 3)
  --duration S       response length (default: 1.1 x the longest measured T20, 0.5-3 s)
  --seed N           base seed of the simulations (default 1)
  --threads N        worker threads (default: all cores); with workers, the pairs of an
                     evaluation get the thread counts they would get here
  --materials FILE   material library (default config/materials.yaml)
  --no-air           the model has no air absorption (whatever the files say)
  --noise-seeds N    extra ray-tracing seeds that measure the simulation's noise, which a
                     cause's gain must stand clear of (default 5; 1-20)
  --no-reflection-term
                     leave the strong measured reflections no model path explains out of
                     the score (B-format pairs); e.g. when the rig's orientation is doubtful
  --no-direction-term
                     leave the directions of the early energy out of the score (B-format
                     pairs; the simulations are then omni): for the same doubt, or speed
  --trace-every-model
                     trace every candidate model's rays instead of replaying the base
                     model's paths for those that differ only in absorption, air or
                     directivity (same expectation; slower)
)";

int runDiagnose(const std::vector<std::string>& raw) {
  std::set<std::string> valued{"measured", "room", "mesh", "out", "causes", "max-causes", "rays", "order", "duration",
                               "seed", "threads", "materials", "noise-seeds"};
  for (const std::string& option : simulationWorkerOptions()) valued.insert(option);
  const Arguments args(raw, valued, {"y-up", "no-air", "no-reflection-term", "no-direction-term", "trace-every-model"});
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (!args.has("measured")) throw UsageError("--measured FILE is required");
  if (!args.has("out")) throw UsageError("--out DIR is required");
  if (args.has("room") && args.has("mesh")) throw UsageError("give at most one of --room and --mesh");

  const Measurements measurements = loadMeasurements(args.value("measured", ""));
  const MeasuredEvidence evidence = measuredEvidence(measurements);
  const MaterialLibrary library = args.has("materials") ? MaterialLibrary::load(args.value("materials", ""))
                                                        : MaterialLibrary::loadDefault();
  std::string room_file = measurements.room_file, mesh_file = measurements.mesh_file;
  UpAxis up = measurements.mesh_up_axis;
  if (args.has("room") || args.has("mesh")) {
    room_file = args.value("room", "");
    mesh_file = args.value("mesh", "");
    up = args.has("y-up") ? UpAxis::kY : UpAxis::kZ;
  }
  if (room_file.empty() && mesh_file.empty()) throw UsageError("no room: give --room or --mesh");
  const RoomUnderTest room = loadRoomUnderTest(room_file, mesh_file, up, measurements, args.has("no-air"), library);

  DiagnosisOptions options;
  if (args.has("causes")) options.causes = commaSeparated(args.value("causes", ""));
  options.max_causes = args.intValue("max-causes", 3);
  if (options.max_causes < 0) throw InputError("--max-causes must not be negative");
  options.noise_seeds = args.intValue("noise-seeds", options.noise_seeds);
  if (options.noise_seeds < 1 || options.noise_seeds > DiagnosisOptions::kMaxNoiseSeeds) {
    throw InputError("--noise-seeds must be 1-" + std::to_string(DiagnosisOptions::kMaxNoiseSeeds));
  }
  options.evaluation.score_reflections = !args.has("no-reflection-term");
  options.evaluation.score_directions = !args.has("no-direction-term");
  options.evaluation.replay_paths = !args.has("trace-every-model");
  SimulationSettings& sim = options.evaluation.simulation;
  const int rays = args.intValue("rays", 10000);
  if (rays <= 0) throw InputError("--rays must be at least 1");
  sim.rays.ray_count = static_cast<std::size_t>(rays);
  sim.image_source_order = args.intValue("order", 3);
  sim.rays.seed = static_cast<std::uint32_t>(args.intValue("seed", 1));
  sim.rays.threads = args.intValue("threads", 0);
  sim.duration_s = args.has("duration") ? args.doubleValue("duration", 1.0) : diagnosisDurationS(evidence);
  if (!(sim.duration_s > 0.0)) throw InputError("--duration must be positive");
  options.evaluation.runner = simulationRunnerFrom(args);

  const Diagnosis diagnosis = reportingWorkerFailures([&] { return diagnose(room, evidence, options); });
  const DiagnosisFiles files = writeDiagnosis(diagnosis, room, evidence, args.value("out", ""));
  std::cout << std::fixed << std::setprecision(2) << "baseline error " << diagnosis.baseline_error_jnd
            << " JND (held out " << diagnosis.baseline_heldout_jnd << ", noise " << diagnosis.noise_jnd << ")\n";
  if (diagnosis.causes.empty()) {
    std::cout << "no cause named (threshold " << diagnosis.threshold_jnd << " JND)\n";
  }
  for (const NamedCause& c : diagnosis.causes) {
    std::cout << c.cause << (c.target.empty() ? "" : " (" + c.target + ")") << ": error " << c.error_before_jnd
              << " -> " << c.error_after_jnd << " JND, held-out gain " << c.heldoutGainJnd() << " JND ("
              << c.over_seeds.mean_jnd << " +- " << c.over_seeds.standard_error_jnd << " over "
              << c.over_seeds.gains.size() << " seeds)\n";
  }
  for (const MeasurementFlag& f : diagnosis.flags) std::cout << "measurement_limits: " << f.pair << ": " << f.issue << "\n";
  if (const auto* remote = dynamic_cast<const RemoteSimulationRunner*>(options.evaluation.runner.get())) {
    const RemoteSimulationRunner::Counts counts = remote->counts();
    std::cout << "simulated on " << remote->description() << ": " << counts.jobs << " simulations in " << counts.batches
              << " batches, the largest " << counts.largest_batch << "\n";
  }
  std::cout << "wrote " << files.json << ", " << files.report << (files.extended_room.empty() ? "" : ", " + files.extended_room)
            << " (" << diagnosis.simulations << " simulations, " << diagnosis.wall_time_s << " s)\n";
  return 0;
}

const CommandRegistration registration({"diagnose", "name what a room's simulation gets wrong against a measurement",
                                         std::string(kHelp) + kSimulationWorkersHelp, runDiagnose});

}  // namespace
}  // namespace room_reverb::tool
