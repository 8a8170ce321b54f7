#include "room_reverb/evaluation/measurement_comparison.h"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/evaluation/simulated_pairs.h"
#include "room_reverb/metrics/impulse_response_metrics.h"

namespace room_reverb::core {
namespace {

using nlohmann::json;

// The request of pair `index`: its own seed, first-order AmbiX where the measured file is
// B-format (so both sides get an RSAO), every thread of the comparison (pairs run one after
// another in this process).
SimulationRequest pairRequest(std::size_t index, const MeasurementPair& pair, bool measured_rir,
                              const SimulationSettings& settings) {
  SimulationRequest request;
  request.source_m = pair.source_m;
  request.listener_m = pair.receiver_m;
  request.settings = settings;
  request.settings.rays.seed = pairSeed(settings.rays.seed, index);
  request.settings.rays.threads = roundThreads(1, settings.rays.threads, 0);
  request.settings.ambisonic_order = measured_rir && isBFormat(pair) ? 1 : 0;
  return request;
}

MeasuredPairComparison comparePair(const SimulationResult& result, double simulation_s, const MeasurementPair& pair,
                                   const PairEvidence* measured, const MeasuredParameters& table) {
  const auto start = std::chrono::steady_clock::now();
  MeasuredPairComparison out;
  out.pair = pair;
  out.stats = result.stats;
  if (measured != nullptr) {
    const PairEvidence simulated = analysePair(pair, result.impulse_response);
    out.bands = compareWithMeasured({simulated.metrics}, parametersFromReport(measured->metrics));
    if (measured->rsao && simulated.rsao) out.reflections = matchReflections(*measured->rsao, *simulated.rsao);
    out.measured_omni = measured->omni;
    out.simulated_omni = simulated.omni;
    out.measured_onset = measured->metrics.onset_sample;
    out.simulated_onset = simulated.metrics.onset_sample;
  } else {
    MetricsOptions options;
    options.resolution = table.resolution;
    out.bands = compareWithMeasured({analyseImpulseResponse(result.impulse_response, 0, options)}, table);
  }
  out.wall_time_s = simulation_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

json optionalNumber(const std::optional<double>& v) { return v && std::isfinite(*v) ? json(*v) : json(nullptr); }

json rowsToJson(const std::vector<BandComparison>& rows) {
  json out = json::array();
  for (const BandComparison& row : rows) {
    json r{{"band_hz", row.nominal_hz}};
    for (ComparedParameter p : kComparedParameters) {
      const std::size_t i = static_cast<std::size_t>(p);
      if (!row.measured[i] && !row.simulated[i]) continue;
      r[toString(p)] = {{"simulated", optionalNumber(row.simulated[i])},
                        {"measured", optionalNumber(row.measured[i])},
                        {"error_jnd", optionalNumber(row.error_jnd[i])}};
    }
    out.push_back(r);
  }
  return out;
}

json reflectionToJson(const RelativeReflection& r) {
  return {{"index", r.index}, {"delay_ms", 1000.0 * r.delay_s}, {"level_db", r.level_db},
          {"azimuth_deg", r.azimuth_deg}, {"elevation_deg", r.elevation_deg}};
}

json matchingToJson(const ReflectionMatching& m) {
  json matched = json::array(), measured_only = json::array(), simulated_only = json::array();
  for (const MatchedReflection& x : m.matched) {
    matched.push_back({{"measured", reflectionToJson(x.measured)},
                       {"simulated", reflectionToJson(x.simulated)},
                       {"time_error_ms", x.time_error_ms},
                       {"direction_error_deg", x.direction_error_deg},
                       {"level_error_db", x.level_error_db}});
  }
  for (const RelativeReflection& r : m.measured_only) measured_only.push_back(reflectionToJson(r));
  for (const RelativeReflection& r : m.simulated_only) simulated_only.push_back(reflectionToJson(r));
  return {{"matched", matched}, {"measured_only", measured_only}, {"simulated_only", simulated_only}};
}

json summaryToJson(const ComparisonSummary& summary) {
  json out{{"overall_mean_abs_error_jnd", optionalNumber(summary.overall_mean_abs_error_jnd)}};
  for (ComparedParameter p : kComparedParameters) {
    const auto& v = summary.mean_abs_error_jnd[static_cast<std::size_t>(p)];
    if (v) out["mean_abs_error_jnd"][toString(p)] = *v;
  }
  return out;
}

std::string fixed(double v, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

std::string matchingMarkdown(const ReflectionMatching& m) {
  std::ostringstream os;
  os << "| measured delay (ms) | simulated delay (ms) | time error (ms) | direction error (deg) | level error (dB) |\n"
     << "| --- | --- | --- | --- | --- |\n";
  for (const MatchedReflection& x : m.matched) {
    os << "| " << fixed(1000.0 * x.measured.delay_s, 2) << " | " << fixed(1000.0 * x.simulated.delay_s, 2) << " | "
       << fixed(x.time_error_ms, 2) << " | " << fixed(x.direction_error_deg, 0) << " | " << fixed(x.level_error_db, 1)
       << " |\n";
  }
  for (const RelativeReflection& r : m.measured_only) {
    os << "| " << fixed(1000.0 * r.delay_s, 2) << " | none | | | |\n";
  }
  for (const RelativeReflection& r : m.simulated_only) {
    os << "| none | " << fixed(1000.0 * r.delay_s, 2) << " | | | |\n";
  }
  return os.str();
}

}  // namespace

MeasurementComparison compareMeasurement(const AcousticScene& scene, const MeasuredEvidence& evidence,
                                         const SimulationSettings& settings,
                                         const std::function<void(std::size_t, const MeasuredPairComparison&)>& progress,
                                         SimulationRunner* runner) {
  if (evidence.positions.empty()) throw InputError("the measurement has no source-receiver pairs to simulate");
  if (!evidence.usesRirs() && evidence.table.empty()) {
    throw InputError("the measurement has neither RIR files nor a parameters table to compare with");
  }
  MeasurementComparison out;
  out.from_rirs = evidence.usesRirs();
  out.resolution = out.from_rirs ? BandResolution::kOctave : evidence.table.resolution;
  out.flags = evidence.flags;
  out.settings = settings;
  std::vector<SimulationRequest> requests;
  for (std::size_t i = 0; i < evidence.positions.size(); ++i) {
    requests.push_back(pairRequest(i, evidence.positions[i], out.from_rirs, settings));
  }
  // With a runner every pair at once; in this process one after another, each reported
  // as it is done (a BRAS CR2 pair at 10^5 rays takes about 15 s).
  std::vector<double> times;
  std::vector<SimulationResult> results;
  if (runner) results = runSimulations(scene, requests, 1, runner, &times);
  std::vector<std::vector<BandComparison>> per_pair;
  for (std::size_t i = 0; i < evidence.positions.size(); ++i) {
    const PairEvidence* measured = out.from_rirs ? &evidence.rirs[i] : nullptr;
    if (!runner) {
      results = runSimulations(scene, {requests[i]}, 1, nullptr, &times);
      out.pairs.push_back(comparePair(results.front(), times.front(), evidence.positions[i], measured, evidence.table));
    } else {
      out.pairs.push_back(comparePair(results[i], times[i], evidence.positions[i], measured, evidence.table));
    }
    per_pair.push_back(out.pairs.back().bands);
    if (progress) progress(i, out.pairs.back());
  }
  // Per band, the means over the pairs; a table's measured value is the same for every
  // pair, so its average is the mean simulation against the table.
  out.average = averageComparisons(per_pair);
  return out;
}

ComparisonSummary summarizeComparison(const std::vector<BandComparison>& rows) {
  ComparisonSummary summary;
  double all = 0.0;
  int all_n = 0;
  for (ComparedParameter p : kComparedParameters) {
    const std::size_t i = static_cast<std::size_t>(p);
    double sum = 0.0;
    int n = 0;
    for (const BandComparison& row : rows) {
      if (row.nominal_hz < 110.0 || row.nominal_hz > 4500.0 || !row.error_jnd[i]) continue;
      sum += std::abs(*row.error_jnd[i]);
      ++n;
    }
    if (n == 0) continue;
    summary.mean_abs_error_jnd[i] = sum / n;
    all += sum;
    all_n += n;
  }
  if (all_n > 0) summary.overall_mean_abs_error_jnd = all / all_n;
  return summary;
}

std::string comparisonToJson(const MeasurementComparison& comparison) {
  json pairs = json::array();
  for (const MeasuredPairComparison& pair : comparison.pairs) {
    json p{{"label", pair.pair.label},
           {"file", pair.pair.file},
           {"source_m", {pair.pair.source_m.x(), pair.pair.source_m.y(), pair.pair.source_m.z()}},
           {"receiver_m", {pair.pair.receiver_m.x(), pair.pair.receiver_m.y(), pair.pair.receiver_m.z()}},
           {"bands", rowsToJson(pair.bands)},
           {"summary", summaryToJson(summarizeComparison(pair.bands))},
           {"rays", pair.stats.rays},
           {"leaked_rays", pair.stats.leaked_rays},
           {"wall_time_s", pair.wall_time_s}};
    if (pair.reflections) p["reflections"] = matchingToJson(*pair.reflections);
    pairs.push_back(p);
  }
  json flags = json::array();
  for (const MeasurementFlag& f : comparison.flags) flags.push_back({{"pair", f.pair}, {"issue", f.issue}, {"detail", f.detail}});
  const SimulationSettings& s = comparison.settings;
  json out{{"resolution", comparison.resolution == BandResolution::kThirdOctave ? "third_octave" : "octave"},
           {"measured_from", comparison.from_rirs ? "rir_files" : "parameter_table"},
           {"simulation",
            {{"mode", toString(s.mode)},
             {"rays", s.rays.ray_count},
             {"image_source_order", s.image_source_order},
             {"duration_s", s.duration_s},
             {"base_seed", s.rays.seed},
             {"air", s.air.enabled},
             {"temperature_c", s.air.temperature_c},
             {"humidity_percent", s.air.humidity_percent}}},
           {"average", rowsToJson(comparison.average)},
           {"summary", summaryToJson(summarizeComparison(comparison.average))},
           {"pairs", pairs},
           {"measurement_limits", flags}};
  return out.dump(2) + "\n";
}

std::string comparisonReportMarkdown(const MeasurementComparison& comparison) {
  std::ostringstream os;
  os << "## Averaged over " << comparison.pairs.size() << " pairs\n\n" << comparisonToMarkdown(comparison.average) << "\n";
  for (const MeasurementFlag& f : comparison.flags) os << "- measurement limit (" << f.issue << ", " << f.pair << "): " << f.detail << "\n";
  for (std::size_t i = 0; i < comparison.pairs.size(); ++i) {
    const MeasuredPairComparison& pair = comparison.pairs[i];
    os << "\n## Pair " << i + 1 << (pair.pair.label.empty() ? "" : " " + pair.pair.label) << "\n\n";
    if (!comparison.from_rirs) os << "Simulated at this pair, against the averaged table.\n\n";
    os << comparisonToMarkdown(pair.bands) << "\n";
    if (pair.reflections) {
      os << "Early reflections (RSAO of the measurement and of the simulation, delays after each one's "
            "direct sound): "
         << pair.reflections->matched.size() << " matched, " << pair.reflections->measured_only.size()
         << " measured only, " << pair.reflections->simulated_only.size() << " simulated only.\n\n"
         << matchingMarkdown(*pair.reflections) << "\n";
    }
  }
  return os.str();
}

}  // namespace room_reverb::core
