// The files of a comparison: JSON, Markdown and the decay-curve figure.
#include <algorithm>
#include <filesystem>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/common/plots.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/evaluation/decay_curves.h"
#include "room_reverb/evaluation/measurement_comparison.h"

namespace room_reverb::core {
namespace {

namespace fs = std::filesystem;
constexpr double kCurveBands[] = {125.0, 250.0, 500.0, 1000.0, 2000.0, 4000.0};
constexpr double kStepS = 0.01;

// One panel per octave band, every pair's measured curve solid and simulated dashed in
// the pair's colour.
void writeDecayCurves(const MeasurementComparison& comparison, const std::string& path) {
  double length = 0.0;
  for (const MeasuredPairComparison& p : comparison.pairs) {
    length = std::max(length, static_cast<double>(p.measured_omni.size()) / kInternalSampleRateHz);
  }
  length = std::min(0.9 * length, 3.0);
  const std::vector<double> t = decayCurveTimes(kStepS, length);
  std::vector<LinePanel> panels;
  for (double band : kCurveBands) {
    LinePanel panel;
    panel.title = std::to_string(static_cast<int>(band)) + " Hz (solid measured, dashed simulated)";
    panel.x_label = "time after the direct sound (s)";
    panel.y_label = "decay (dB)";
    panel.y_range = std::make_pair(-70.0, 2.0);
    for (std::size_t i = 0; i < comparison.pairs.size(); ++i) {
      const MeasuredPairComparison& p = comparison.pairs[i];
      const std::string name = p.pair.label.empty() ? "pair " + std::to_string(i + 1) : p.pair.label;
      panel.series.push_back({name, t,
                              bandDecayCurveDb(p.measured_omni, kInternalSampleRateHz, p.measured_onset, band, kStepS, length),
                              plotPalette(i), false});
      panel.series.push_back({"", t,
                              bandDecayCurveDb(p.simulated_omni, kInternalSampleRateHz, p.simulated_onset, band, kStepS, length),
                              plotPalette(i), true});
    }
    panels.push_back(panel);
  }
  writeLinePlots(path, panels, 2);
}

}  // namespace

std::vector<std::string> writeComparison(const MeasurementComparison& comparison, const std::string& directory) {
  createFolder(directory);
  std::vector<std::string> files{(fs::path(directory) / "comparison.json").string(),
                                 (fs::path(directory) / "report.md").string()};
  writeTextFile(files[0], comparisonToJson(comparison));
  writeTextFile(files[1], "# Measured vs simulated\n\n" + comparisonReportMarkdown(comparison));
  if (comparison.from_rirs) {
    files.push_back((fs::path(directory) / "decay_curves.png").string());
    writeDecayCurves(comparison, files.back());
  }
  return files;
}

}  // namespace room_reverb::core
