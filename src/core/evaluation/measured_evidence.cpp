#include "room_reverb/evaluation/measured_evidence.h"

#include <cmath>
#include <sstream>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/audio/clipping.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/common/error.h"
#include "room_reverb/evaluation/measured_reflections.h"
#include "room_reverb/metrics/impulse_response_metrics.h"
#include "room_reverb/rsao/rsao_estimator.h"

namespace room_reverb::core {
namespace {

std::string nameOf(const MeasurementPair& pair) { return pair.label.empty() ? pair.file : pair.label; }

AudioBuffer readPairFile(const MeasurementPair& pair) {
  AudioBuffer buffer = readAudioFile(pair.file);
  validateAudioBuffer(buffer, pair.file);
  const std::size_t expected = pair.format == "omni" ? 1 : 4;
  if (buffer.channelCount() != expected) {
    std::ostringstream os;
    os << pair.file << ": format " << pair.format << " needs " << expected << " channel(s), the file has "
       << buffer.channelCount();
    throw InputError(os.str());
  }
  if (buffer.sample_rate_hz < 16000.0) {
    std::ostringstream os;
    os << pair.file << ": sample rate " << buffer.sample_rate_hz
       << " Hz is too low to compare the 8 kHz band; record at 44.1 or 48 kHz";
    throw InputError(os.str());
  }
  return buffer;
}

void flagLimits(const PairEvidence& evidence, const AudioBuffer& as_recorded, std::vector<MeasurementFlag>& flags) {
  const std::string who = nameOf(evidence.pair);
  for (std::size_t c = 0; c < as_recorded.channelCount(); ++c) {
    const std::size_t at = findClippedRun(as_recorded.channels[c], 0, 3);
    if (at < as_recorded.channels[c].size()) {
      std::ostringstream os;
      os << "channel " << c << " is clipped (a flat top at " << at << " samples): levels and DRR are not reliable";
      flags.push_back({who, "clipping", os.str()});
      break;
    }
  }
  std::ostringstream short_range;
  for (const AcousticParameters& band : evidence.metrics.bands) {
    if (band.nominal_hz < 125.0 || band.nominal_hz > 8000.0) continue;
    if (band.decay_range_db < kRangeNeededForT20Db) short_range << " " << band.nominal_hz << " Hz (" << std::lround(band.decay_range_db) << " dB)";
  }
  if (!short_range.str().empty()) {
    flags.push_back({who, "noise_floor",
                     "decay range below the 35 dB T20 needs in" + short_range.str() + ": those bands are left out"});
  }
  if (isBFormat(evidence.pair)) {
    const std::string warning = checkAmbisonicFormat(as_recorded, parseAmbisonicFormat(evidence.pair.format));
    if (!warning.empty()) flags.push_back({who, "bformat_convention", warning});
  }
}

}  // namespace

PairEvidence analysePair(const MeasurementPair& pair, const AudioBuffer& response) {
  PairEvidence evidence;
  evidence.pair = pair;
  const AudioBuffer internal = toInternalRate(response);
  evidence.omni = internal.channels.front();
  MetricsOptions options;
  options.recorded_bandwidth_hz = 0.5 * response.sample_rate_hz;
  evidence.metrics = computeRoomAcousticParameters(evidence.omni, internal.sample_rate_hz, options);
  evidence.early = earlyEnergyProfile(evidence.omni, internal.sample_rate_hz, evidence.metrics.onset_sample);
  if (internal.channelCount() >= 4) {
    // Without a clear direct sound (a source turned away, an occluded path) there is no
    // RSAO to place reflections from; the ISO parameters and the early profile still hold.
    try {
      evidence.rsao = estimateRsao(internal, AmbisonicFormat::kAmbiX);
    } catch (const InputError&) {
      evidence.rsao.reset();
    }
    evidence.reflections = reflectionEvidence(internal);
    // A response that ends within the early reflections has no profile; the rest holds.
    try {
      evidence.directions = earlyDirectionProfile(internal, evidence.metrics.onset_sample);
    } catch (const InputError&) {
      evidence.directions.reset();
    }
  }
  return evidence;
}

MeasuredEvidence measuredEvidence(const Measurements& measurements) {
  MeasuredEvidence evidence;
  evidence.positions = measurements.pairs;
  evidence.table = measurements.parameters;
  std::size_t with_file = 0;
  for (const MeasurementPair& pair : measurements.pairs) with_file += pair.file.empty() ? 0 : 1;
  if (with_file > 0 && with_file < measurements.pairs.size()) {
    throw InputError("measurements: " + std::to_string(with_file) + " of " + std::to_string(measurements.pairs.size()) +
                     " pairs have a file; give a file for every pair or for none");
  }
  if (with_file == 0 && evidence.table.empty()) {
    throw InputError("measurements: no RIR files and no parameters table: nothing to compare with");
  }
  if (measurements.pairs.empty()) throw InputError("measurements: no source-receiver pairs to simulate");
  for (const MeasurementPair& pair : measurements.pairs) {
    if (pair.file.empty()) continue;
    const AudioBuffer recorded = readPairFile(pair);
    const AudioBuffer ambix = pair.format == "omni" ? recorded : toAmbix(recorded, parseAmbisonicFormat(pair.format));
    try {
      evidence.rirs.push_back(analysePair(pair, ambix));
    } catch (const InputError& e) {
      throw InputError(pair.file + ": " + e.what());
    }
    flagLimits(evidence.rirs.back(), recorded, evidence.flags);
  }
  return evidence;
}

}  // namespace room_reverb::core
