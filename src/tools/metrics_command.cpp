// room_reverb metrics: ISO 3382-1 parameters of impulse-response files.
#include <iostream>

#include "arguments.h"
#include "command.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/metrics/impulse_response_metrics.h"
#include "room_reverb/metrics/metrics_report_format.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb metrics RIR.wav [RIR2.wav ...] [--json] [--bands octave|third] [--channel N]

Room-acoustic parameters after ISO 3382-1 of each impulse-response file: T20, T30, EDT,
C50, C80, D50, centre time Ts and the direct-to-reverberant ratio, per octave band
(63 Hz - 16 kHz) or third-octave band (20 Hz - 20 kHz), and broadband.

  --json           print one JSON object per file (a JSON array for several files)
  --bands KIND     octave (default) or third
  --channel N      channel to analyse, from 0 (default 0: W of a B-format file)

Files at other rates than 48 kHz are resampled to it first. Values that cannot be
measured (too little decay above the noise floor, a band above the recording's Nyquist
frequency) are shown as '-' (null in JSON) with the reason.
Exit status: 0 on success, 2 with one line on stderr for bad input.
)";

int runMetrics(const std::vector<std::string>& args) {
  const Arguments arguments(args, {"bands", "channel"}, {"json"});
  if (arguments.positional().empty()) throw UsageError("no impulse-response file given");
  MetricsOptions options;
  options.resolution = parseBandResolution(arguments.value("bands", "octave"));
  const int channel = arguments.intValue("channel", 0);
  const bool json = arguments.has("json");
  const auto& files = arguments.positional();

  // Analyse every file before printing, so bad input prints nothing but the error line.
  std::vector<std::string> outputs;
  for (const auto& file : files) {
    const AudioBuffer rir = readAudioFile(file);
    const MetricsReport report = analyseImpulseResponse(rir, channel, options);
    const MetricsSource source{file, channel, rir.sample_rate_hz};
    outputs.push_back(json ? metricsToJson(report, source, files.size() > 1 ? 4 : 2)
                           : metricsToTable(report, source));
  }
  if (json && files.size() > 1) {
    std::cout << "[\n";
    for (std::size_t i = 0; i < outputs.size(); ++i) std::cout << outputs[i] << (i + 1 < outputs.size() ? ",\n" : "\n");
    std::cout << "]\n";
  } else {
    for (std::size_t i = 0; i < outputs.size(); ++i) std::cout << (i ? "\n" : "") << outputs[i] << (json ? "\n" : "");
  }
  return 0;
}

const CommandRegistration registration({"metrics", "ISO 3382-1 room-acoustic parameters of RIR files", kHelp, runMetrics});

}  // namespace
}  // namespace room_reverb::tool
