#include "room_reverb/diagnosis/diagnosis_plots.h"

#include <cmath>
#include <filesystem>
#include <map>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/common/plots.h"
#include "room_reverb/evaluation/decay_curves.h"
#include "room_reverb/metrics/energy_decay.h"

namespace room_reverb::core {
namespace {

const PlotColor kMeasured{0, 0, 0};
const PlotColor kBefore{214, 39, 40};
const PlotColor kAfter{31, 119, 180};
const std::vector<double> kCurveBands{125, 500, 2000, 8000};

std::vector<double> curveOf(const PairEvidence& pair, double band_hz, double step_s, double length_s) {
  return bandDecayCurveDb(pair.omni, kInternalSampleRateHz, pair.metrics.onset_sample, band_hz, step_s, length_s);
}

std::string decayCurves(const Diagnosis& d, const MeasuredEvidence& evidence, const std::string& path) {
  if (d.before.predictions.empty()) return "";
  // The first pair: it is a fit pair and has a measured response if any pair has one.
  const double step = 0.01;
  double length = 0.0;
  for (const PairPrediction& p : d.before.predictions) {
    length = std::max(length, static_cast<double>(p.analysis.omni.size()) / kInternalSampleRateHz);
  }
  length = std::min(length * 0.9, 3.0);
  const std::vector<double> t = decayCurveTimes(step, length);
  std::vector<LinePanel> panels;
  for (double band : kCurveBands) {
    LinePanel panel;
    panel.title = "pair 1, " + std::to_string(static_cast<int>(band)) + " Hz";
    panel.x_label = "time after the direct sound (s)";
    panel.y_label = "decay (dB)";
    panel.y_range = std::make_pair(-70.0, 2.0);
    if (evidence.usesRirs()) panel.series.push_back({"measured", t, curveOf(evidence.rirs.front(), band, step, length), kMeasured, false});
    panel.series.push_back({"model before", t, curveOf(d.before.predictions.front().analysis, band, step, length), kBefore, true});
    if (!d.after.predictions.empty()) {
      panel.series.push_back({"model after", t, curveOf(d.after.predictions.front().analysis, band, step, length), kAfter, false});
    }
    panels.push_back(panel);
  }
  writeLinePlots(path, panels, 2);
  return path;
}

// Mean signed error per group and band over all pairs (for `directions`, mean absolute).
std::map<std::string, std::map<double, double>> signedErrors(const Evaluation& e) {
  std::map<std::string, std::map<double, std::pair<double, int>>> sums;
  for (const ErrorTerm& term : e.terms) {
    auto& [s, n] = sums[term.group][term.band_hz];
    // The six directions' levels are relative to the window's omni energy: their signed
    // errors cancel in a mean, so the panel shows how far they are off.
    s += term.group == "directions" ? std::abs(term.error_jnd) : term.error_jnd;
    ++n;
  }
  std::map<std::string, std::map<double, double>> out;
  for (const auto& [group, bands] : sums) {
    for (const auto& [band, sn] : bands) out[group][band] = sn.first / sn.second;
  }
  return out;
}

std::string errorPerBand(const Diagnosis& d, const std::string& path) {
  const auto before = signedErrors(d.before), after = signedErrors(d.after);
  std::vector<BarPanel> panels;
  for (const auto& [group, bands] : before) {
    BarPanel panel;
    panel.title = group + (group == "early"         ? " (mean over windows)"
                           : group == "reflections" ? " (unmatched strong, per pair)"
                           : group == "directions"  ? " (mean |error| over the six)"
                                                    : "");
    panel.y_label = "error (JND)";
    panel.x_label = "octave band (Hz)";
    panel.reference_lines = {-1.0, 1.0};
    BarGroup b{"before", {}, kBefore}, a{"after", {}, kAfter};
    for (const auto& [band, value] : bands) {
      panel.categories.push_back(band <= 0.0 ? std::string("broadband")
                                 : band >= 1000 ? std::to_string(static_cast<int>(band / 1000)) + "k"
                                              : std::to_string(static_cast<int>(band)));
      b.values.push_back(value);
      const auto g = after.find(group);
      a.values.push_back(g != after.end() && g->second.count(band) ? g->second.at(band) : std::nan(""));
    }
    panel.groups = {b, a};
    panels.push_back(panel);
  }
  if (panels.empty()) return "";
  writeBarCharts(path, panels, 3);
  return path;
}

}  // namespace

std::vector<std::string> writeDiagnosisPlots(const Diagnosis& diagnosis, const MeasuredEvidence& evidence,
                                             const std::string& directory) {
  namespace fs = std::filesystem;
  std::vector<std::string> written;
  for (const std::string& p : {decayCurves(diagnosis, evidence, (fs::path(directory) / "decay_curves.png").string()),
                               errorPerBand(diagnosis, (fs::path(directory) / "error_per_band.png").string())}) {
    if (!p.empty()) written.push_back(p);
  }
  return written;
}

}  // namespace room_reverb::core
