#include "room_reverb/metrics/metrics_report_format.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

namespace room_reverb::core {
namespace {

nlohmann::json optionalValue(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

nlohmann::json parametersJson(const AcousticParameters& p, bool with_band) {
  nlohmann::json j;
  if (with_band) {
    j["center_hz"] = p.nominal_hz;
    j["exact_center_hz"] = p.center_hz;
  }
  j["t20_s"] = optionalValue(p.t20_s);
  j["t30_s"] = optionalValue(p.t30_s);
  j["edt_s"] = optionalValue(p.edt_s);
  j["c50_db"] = optionalValue(p.c50_db);
  j["c80_db"] = optionalValue(p.c80_db);
  j["d50"] = optionalValue(p.d50);
  j["ts_s"] = optionalValue(p.ts_s);
  j["drr_db"] = optionalValue(p.drr_db);
  j["decay_range_db"] = p.decay_range_db;
  j["reliable"] = p.reliable;
  j["reason"] = p.reason;
  return j;
}

std::string cell(const std::optional<double>& value, const char* format) {
  if (!value) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), format, *value);
  return text;
}

std::string bandLabel(double nominal_hz) {
  char text[16];
  if (nominal_hz >= 1000.0) {
    std::snprintf(text, sizeof(text), "%gk", nominal_hz / 1000.0);
  } else {
    std::snprintf(text, sizeof(text), "%g", nominal_hz);
  }
  return text;
}

}  // namespace

std::string metricsToJson(const MetricsReport& report, const MetricsSource& source, int indent) {
  nlohmann::json j;
  j["file"] = source.file;
  j["sample_rate_hz"] = source.file_sample_rate_hz > 0.0 ? source.file_sample_rate_hz : report.sample_rate_hz;
  j["analysis_sample_rate_hz"] = report.sample_rate_hz;
  j["channel"] = source.channel;
  j["onset_s"] = report.onset_s;
  j["bands_kind"] = toString(report.resolution);
  j["bands"] = nlohmann::json::array();
  for (const auto& band : report.bands) j["bands"].push_back(parametersJson(band, true));
  j["broadband"] = parametersJson(report.broadband, false);
  return j.dump(indent);
}

std::string metricsToTable(const MetricsReport& report, const MetricsSource& source) {
  std::ostringstream os;
  char line[160];
  os << source.file << "  (channel " << source.channel << ", onset "
     << cell(report.onset_s * 1000.0, "%.2f") << " ms)\n";
  std::snprintf(line, sizeof(line), "%8s %8s %8s %8s %8s %6s %8s %9s\n", "band Hz", "T20 s",
                "T30 s", "EDT s", "C80 dB", "D50", "DRR dB", "range dB");
  os << line;
  std::ostringstream notes;
  auto row = [&](const std::string& label, const AcousticParameters& p) {
    std::snprintf(line, sizeof(line), "%8s %8s %8s %8s %8s %6s %8s %9.1f\n", label.c_str(),
                  cell(p.t20_s, "%.3f").c_str(), cell(p.t30_s, "%.3f").c_str(),
                  cell(p.edt_s, "%.3f").c_str(), cell(p.c80_db, "%.2f").c_str(),
                  cell(p.d50, "%.2f").c_str(), cell(p.drr_db, "%.2f").c_str(), p.decay_range_db);
    os << line;
    if (!p.reason.empty()) notes << "  " << label << ": " << p.reason << "\n";
  };
  for (const auto& band : report.bands) row(bandLabel(band.nominal_hz), band);
  row("broad", report.broadband);
  if (!notes.str().empty()) os << " unavailable values:\n" << notes.str();
  return os.str();
}

}  // namespace room_reverb::core
