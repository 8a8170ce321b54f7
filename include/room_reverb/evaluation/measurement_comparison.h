#pragma once
// The comparison: a measurement (RIR files with positions, or a table of averaged
// parameters with positions) against the simulation of a room, per pair and averaged,
// for the `compare` tool and the evaluation node's ~compare service alike.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/acoustics/simulation_runner.h"
#include "room_reverb/evaluation/measured_evidence.h"
#include "room_reverb/evaluation/parameter_comparison.h"
#include "room_reverb/evaluation/reflection_matching.h"

namespace room_reverb::core {

struct MeasuredPairComparison {
  MeasurementPair pair;
  // Rows at the measurement's resolution: against this pair's RIR, or (table only)
  // against the averaged table, which is all a table gives per pair.
  std::vector<BandComparison> bands;
  // B-format measurements with an RSAO on both sides.
  std::optional<ReflectionMatching> reflections;
  // 48 kHz omni responses and their onsets, for decay curves (RIR measurements only).
  std::vector<float> measured_omni, simulated_omni;
  std::size_t measured_onset = 0, simulated_onset = 0;
  RayTracingStats stats;
  double wall_time_s = 0.0;
};

struct MeasurementComparison {
  BandResolution resolution = BandResolution::kOctave;
  bool from_rirs = false;
  std::vector<MeasuredPairComparison> pairs;
  // Averaged over the pairs: simulated and measured means, errors of the means.
  std::vector<BandComparison> average;
  std::vector<MeasurementFlag> flags;
  SimulationSettings settings;
};

// Simulates every pair (pair i with pairSeed(settings.rays.seed, i); first-order AmbiX
// where the measured file is B-format, so both sides get an RSAO) and compares. The pairs
// are simulated by `runner` (null: in this process, one after another, each on every
// thread of settings.rays.threads), with the same results wherever they run.
// `progress` (may be empty) is called after each pair's comparison.
MeasurementComparison compareMeasurement(
    const AcousticScene& scene, const MeasuredEvidence& evidence, const SimulationSettings& settings,
    const std::function<void(std::size_t, const MeasuredPairComparison&)>& progress = {},
    SimulationRunner* runner = nullptr);

// Each parameter's mean of |error| in JND over the average's rows (125 Hz - 4 kHz octaves
// or their thirds), and over all of them; empty where nothing was compared.
struct ComparisonSummary {
  std::array<std::optional<double>, kComparedParameterCount> mean_abs_error_jnd;
  std::optional<double> overall_mean_abs_error_jnd;
};
ComparisonSummary summarizeComparison(const std::vector<BandComparison>& rows);

// The whole comparison as JSON (pairs, rows, reflections, summary, flags) and as a
// Markdown report (average table, per-pair tables, reflection matches).
std::string comparisonToJson(const MeasurementComparison& comparison);
std::string comparisonReportMarkdown(const MeasurementComparison& comparison);

// Writes DIR/comparison.json, DIR/report.md and, for RIR measurements, DIR/decay_curves.png
// (measured and simulated energy decay per octave band, every pair); returns the paths.
std::vector<std::string> writeComparison(const MeasurementComparison& comparison, const std::string& directory);

}  // namespace room_reverb::core
