// room_reverb compare: simulate the pairs of a measurement and set the simulated
// room-acoustic parameters against the measured ones, in just-noticeable differences.
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "arguments.h"
#include "command.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/evaluation/measurement_comparison.h"
#include "simulation_arguments.h"
#include "simulation_workers.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelpHead = R"(usage: room_reverb compare --measurements FILE [--out DIR] [--markdown OUT] [--pairs N]
                           [--room ROOM.yaml | --mesh FILE [--y-up]] [simulation options]

Simulates every source-receiver pair of a measurements file (measurements.yaml, DESIGN.md)
in the room it names (or the --room / --mesh given), analyses each simulated RIR as the
metrics command analyses a measured one and sets it against the measurement, per pair and
averaged over the pairs: T20, T30, EDT, C50, C80, D50, Ts and DRR per band, as values and
as errors in just-noticeable differences (T 5 %, EDT 5 %, C 1 dB, D50 0.05, Ts 10 ms,
DRR 1 dB). A measurement with RIR files is compared pair by pair (octave bands), and
B-format files also by their early reflections: the RSAO of the measured and of the
simulated RIR, matched in time after the direct sound (time, direction and level errors;
reflections without a counterpart on either side). A parameters table is compared at its
own resolution; third-octave tables are also reduced to octaves (each octave the mean of
its thirds, for simulated and measured alike).

  --measurements FILE  the measurements (pairs with positions and RIR files, or a
                       parameters table; the room's mesh or room model, air conditions)
  --out DIR            write DIR/comparison.json, DIR/report.md and, for RIR files,
                       DIR/decay_curves.png
  --markdown OUT       write the printed tables and the run's settings as Markdown
  --pairs N            use only the first N pairs (a quick look)
  --room, --mesh, --y-up   simulate this room instead of the file's
)";

std::string summaryLine(const std::vector<BandComparison>& octaves, ComparedParameter p) {
  int within = 0, total = 0;
  for (const BandComparison& row : octaves) {
    if (row.nominal_hz < 125.0 || row.nominal_hz > 4000.0) continue;
    const auto& e = row.error_jnd[static_cast<std::size_t>(p)];
    if (!e) continue;
    ++total;
    if (std::abs(*e) <= 1.0) ++within;
  }
  std::ostringstream os;
  os << toString(p) << " within 1 JND in " << within << " of " << total << " octaves 125 Hz - 4 kHz";
  return os.str();
}

int runCompare(const std::vector<std::string>& raw) {
  std::set<std::string> valued = simulationValueOptions();
  valued.insert({"measurements", "markdown", "pairs", "room", "mesh", "out"});
  for (const std::string& option : simulationWorkerOptions()) valued.insert(option);
  std::set<std::string> flags = simulationFlags();
  flags.insert("y-up");
  const Arguments args(raw, valued, flags);
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (!args.has("measurements")) throw UsageError("--measurements FILE is required");
  if (args.has("room") && args.has("mesh")) throw UsageError("give at most one of --room and --mesh");

  Measurements measurements = loadMeasurements(args.value("measurements", ""));
  if (measurements.pairs.empty()) throw InputError("the measurements file has no source-receiver pairs to simulate");
  if (args.has("pairs")) {
    const int n = args.intValue("pairs", 0);
    if (n <= 0) throw InputError("--pairs must be at least 1");
    measurements.pairs.resize(std::min(measurements.pairs.size(), static_cast<std::size_t>(n)));
  }
  const MeasuredEvidence evidence = measuredEvidence(measurements);
  SceneFiles files{measurements.room_file, measurements.mesh_file, measurements.mesh_up_axis, false};
  if (args.has("room") || args.has("mesh")) {
    files = SceneFiles{args.value("room", ""), args.value("mesh", ""), args.has("y-up") ? UpAxis::kY : UpAxis::kZ, false};
  }
  if (files.room_file.empty() && files.mesh_file.empty()) {
    throw InputError("no room to simulate: the measurements file names no room or mesh; give --room or --mesh");
  }
  SimulationSettings settings = simulationSettingsFrom(args);
  AirConditions air = measurements.air.value_or(AirConditions{});
  const AcousticScene scene = sceneFrom(files, args, air);
  settings.air = air;

  const std::size_t n_pairs = evidence.positions.size();
  const std::shared_ptr<SimulationRunner> runner = simulationRunnerFrom(args);
  const MeasurementComparison comparison = reportingWorkerFailures([&] {
    return compareMeasurement(
        scene, evidence, settings,
        [&](std::size_t i, const MeasuredPairComparison& pair) {
          std::cerr << "pair " << i + 1 << "/" << n_pairs << " " << pair.pair.label << ": " << std::fixed
                    << std::setprecision(1) << pair.wall_time_s << " s, " << pair.stats.leaked_rays << " rays leaked\n";
        },
        runner.get());
  });
  std::vector<double> times;
  std::size_t leaked = 0, rays = 0;
  for (const MeasuredPairComparison& pair : comparison.pairs) {
    times.push_back(pair.wall_time_s);
    leaked += pair.stats.leaked_rays;
    rays += pair.stats.rays;
  }
  std::sort(times.begin(), times.end());

  const bool thirds = comparison.resolution == BandResolution::kThirdOctave;
  const std::vector<BandComparison> octaves = thirds ? thirdsToOctaves(comparison.average) : comparison.average;
  std::ostringstream report;
  // The physics switches that are on, so that a table says which variant made it.
  std::string switches;
  if (settings.diffraction_scattering) switches += ", diffraction scattering";
  if (settings.low_band == LowBandMethod::kWave) {
    std::ostringstream wave;
    wave << ", wave low band below " << settings.wave.crossover_hz << " Hz";
    switches += wave.str();
  }
  if (settings.bands == BandResolution::kThirdOctave) switches += ", third octaves";
  report << "Simulated: " << n_pairs << " pairs, mode " << toString(settings.mode) << switches << ", "
         << settings.rays.ray_count << " rays, image-source order " << settings.image_source_order << ", "
         << settings.duration_s << " s, air " << (air.enabled ? "on" : "off") << " (" << air.temperature_c << " C, "
         << air.humidity_percent << " %), seeds " << settings.rays.seed << ".." << settings.rays.seed + n_pairs - 1
         << ". Median wall time per pair " << std::fixed << std::setprecision(2) << times[times.size() / 2]
         << " s; leaked rays " << std::setprecision(2) << (rays > 0 ? 100.0 * static_cast<double>(leaked) / static_cast<double>(rays) : 0.0)
         << " %. Measured: " << (comparison.from_rirs ? "RIR files, compared pair by pair" : "a parameters table")
         << ".\n\n";
  report << "Octave bands, averaged over the pairs" << (thirds ? " (each value the mean of the octave's third octaves)" : "")
         << ":\n\n" << comparisonToMarkdown(octaves) << "\n";
  for (ComparedParameter p : kComparedParameters) {
    // Only the parameters the measurement gives.
    if (std::any_of(octaves.begin(), octaves.end(),
                    [p](const BandComparison& row) { return row.measured[static_cast<std::size_t>(p)].has_value(); })) {
      report << "- " << summaryLine(octaves, p) << "\n";
    }
  }
  if (thirds) report << "\nThird-octave bands:\n\n" << comparisonToMarkdown(comparison.average);
  for (const MeasuredPairComparison& pair : comparison.pairs) {
    if (!pair.reflections) continue;
    report << "\nEarly reflections of " << (pair.pair.label.empty() ? pair.pair.file : pair.pair.label) << ": "
           << pair.reflections->matched.size() << " matched, " << pair.reflections->measured_only.size()
           << " measured only, " << pair.reflections->simulated_only.size() << " simulated only";
  }
  if (comparison.from_rirs) report << "\n";

  std::cout << report.str();
  if (args.has("markdown")) writeTextFile(args.value("markdown", ""), report.str());
  if (args.has("out")) {
    for (const std::string& file : writeComparison(comparison, args.value("out", ""))) std::cerr << "wrote " << file << "\n";
  }
  return 0;
}

const CommandRegistration registration({"compare", "simulate a measurement's pairs and compare parameters (JND)",
                                         std::string(kHelpHead) + kSimulationOptionsHelp + kSimulationWorkersHelp, runCompare});

}  // namespace
}  // namespace room_reverb::tool
