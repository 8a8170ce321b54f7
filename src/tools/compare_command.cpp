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
#include "room_reverb/evaluation/parameter_comparison.h"
#include "room_reverb/evaluation/simulated_pairs.h"
#include "simulation_arguments.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelpHead = R"(usage: room_reverb compare --measurements FILE [--markdown OUT] [--pairs N]
                           [--room ROOM.yaml | --mesh FILE [--y-up]] [simulation options]

Simulates every source-receiver pair of a measurements file (measurements.yaml, DESIGN.md)
in the room it names (or the --room / --mesh given), analyses each simulated RIR as the
metrics command analyses a measured one, averages over the pairs and prints simulated,
measured and the error in just-noticeable differences (T20 and EDT 5 %, C80 1 dB, D50
0.05) per band of the measured table; third-octave tables are also reduced to octaves
(each octave the mean of its thirds, for simulated and measured alike).

  --measurements FILE  the measurements (pairs with positions, a parameters table, and
                       the room's mesh or room model and air conditions)
  --markdown OUT       also write the tables and the run's settings as Markdown
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
  valued.insert({"measurements", "markdown", "pairs", "room", "mesh"});
  std::set<std::string> flags = simulationFlags();
  flags.insert("y-up");
  const Arguments args(raw, valued, flags);
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (!args.has("measurements")) throw UsageError("--measurements FILE is required");
  if (args.has("room") && args.has("mesh")) throw UsageError("give at most one of --room and --mesh");

  const Measurements measurements = loadMeasurements(args.value("measurements", ""));
  if (measurements.pairs.empty()) throw InputError("the measurements file has no source-receiver pairs to simulate");
  if (measurements.parameters.empty()) throw InputError("the measurements file has no parameters table to compare with");
  SceneFiles files{measurements.room_file, measurements.mesh_file, measurements.mesh_up_axis, false};
  if (args.has("room") || args.has("mesh")) {
    files = SceneFiles{args.value("room", ""), args.value("mesh", ""), args.has("y-up") ? UpAxis::kY : UpAxis::kZ, false};
  }
  if (files.room_file.empty() && files.mesh_file.empty()) {
    throw InputError("no room to simulate: the measurements file names no room or mesh; give --room or --mesh");
  }
  SimulationSettings settings = simulationSettingsFrom(args);
  settings.ambisonic_order = 0;  // the parameters are omni ones
  AirConditions air = measurements.air.value_or(AirConditions{});
  const AcousticScene scene = sceneFrom(files, args, air);
  settings.air = air;

  std::vector<MeasurementPair> pairs = measurements.pairs;
  if (args.has("pairs")) {
    const int n = args.intValue("pairs", 0);
    if (n <= 0) throw InputError("--pairs must be at least 1");
    pairs.resize(std::min(pairs.size(), static_cast<std::size_t>(n)));
  }
  const auto simulated = simulatePairs(scene, pairs, settings, measurements.parameters.resolution,
                                       [&](std::size_t i, const SimulatedPair& pair) {
                                         std::cerr << "pair " << i + 1 << "/" << pairs.size() << " "
                                                   << pairs[i].label << ": " << std::fixed << std::setprecision(1)
                                                   << pair.wall_time_s << " s, " << pair.stats.leaked_rays
                                                   << " rays leaked\n";
                                       });
  std::vector<MetricsReport> reports;
  std::vector<double> times;
  std::size_t leaked = 0, rays = 0;
  for (const SimulatedPair& pair : simulated) {
    reports.push_back(pair.metrics);
    times.push_back(pair.wall_time_s);
    leaked += pair.stats.leaked_rays;
    rays += pair.stats.rays;
  }
  std::sort(times.begin(), times.end());

  const std::vector<BandComparison> rows = compareWithMeasured(reports, measurements.parameters);
  const bool thirds = measurements.parameters.resolution == BandResolution::kThirdOctave;
  const std::vector<BandComparison> octaves = thirds ? thirdsToOctaves(rows) : rows;

  std::ostringstream report;
  report << "Simulated: " << pairs.size() << " pairs, mode " << toString(settings.mode) << ", "
         << settings.rays.ray_count << " rays, image-source order " << settings.image_source_order << ", "
         << settings.duration_s << " s, air " << (air.enabled ? "on" : "off") << " (" << air.temperature_c << " C, "
         << air.humidity_percent << " %), seeds " << settings.rays.seed << ".." << settings.rays.seed + pairs.size() - 1
         << ". Median wall time per pair " << std::fixed << std::setprecision(2) << times[times.size() / 2]
         << " s; leaked rays " << std::setprecision(2) << (rays > 0 ? 100.0 * static_cast<double>(leaked) / static_cast<double>(rays) : 0.0)
         << " %.\n\n";
  report << "Octave bands" << (thirds ? " (each value the mean of the octave's third octaves)" : "") << ":\n\n"
         << comparisonToMarkdown(octaves) << "\n";
  for (ComparedParameter p : kComparedParameters) {
    // Only the parameters the measurement gives.
    if (std::any_of(octaves.begin(), octaves.end(),
                    [p](const BandComparison& row) { return row.measured[static_cast<std::size_t>(p)].has_value(); })) {
      report << "- " << summaryLine(octaves, p) << "\n";
    }
  }
  if (thirds) report << "\nThird-octave bands:\n\n" << comparisonToMarkdown(rows);

  std::cout << report.str();
  if (args.has("markdown")) writeTextFile(args.value("markdown", ""), report.str());
  return 0;
}

const CommandRegistration registration({"compare", "simulate a measurement's pairs and compare parameters (JND)",
                                         std::string(kHelpHead) + kSimulationOptionsHelp, runCompare});

}  // namespace
}  // namespace room_reverb::tool
