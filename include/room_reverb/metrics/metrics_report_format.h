#pragma once
// Text forms of a MetricsReport: the JSON of DESIGN.md ("Metrics") and a readable table.
#include <string>

#include "room_reverb/metrics/room_acoustic_parameters.h"

namespace room_reverb::core {

struct MetricsSource {
  std::string file;          // the analysed file, as the user named it
  int channel = 0;           // analysed channel
  double file_sample_rate_hz = 0.0;  // the file's own rate (analysis may run at 48 kHz)
};

// One JSON object: {"file", "sample_rate_hz", "channel", "onset_s", "bands": [...],
// "broadband": {...}}; unavailable values are null with reliable=false and the reason.
std::string metricsToJson(const MetricsReport& report, const MetricsSource& source, int indent = 2);

// A fixed-width table, one row per band plus broadband, with T20, T30, EDT, C80, D50 and
// DRR; unavailable values print as "-" and reasons are listed under the table.
std::string metricsToTable(const MetricsReport& report, const MetricsSource& source);

}  // namespace room_reverb::core
