#include "room_reverb/rsao/rsao_estimator.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "room_reverb/audio/clipping.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/common/error.h"
#include "room_reverb/metrics/onset.h"
#include "room_reverb/rsao/onset_ramp_fit.h"

namespace room_reverb::core {
namespace {

constexpr double kFs = kInternalSampleRateHz;
constexpr double kMinLateS = 0.1;             // estimateLateReverb's least analysis span
constexpr double kProminenceGapS = 0.0025;    // after the direct sound, before its reference span
constexpr double kProminenceSpanS = 0.050;

bool isSquare(std::size_t n) {
  const auto root = static_cast<std::size_t>(std::lround(std::sqrt(static_cast<double>(n))));
  return root * root == n;
}

AudioBuffer firstOrderAmbix48k(const AudioBuffer& input, AmbisonicFormat format, std::vector<std::string>& warnings) {
  validateAudioBuffer(input, "RSAO: the impulse response");
  const std::size_t channels = input.channelCount();
  const bool higher_order_ambix = format == AmbisonicFormat::kAmbiX && channels > 4 && channels <= 16 && isSquare(channels);
  if (channels != 4 && !higher_order_ambix) {
    std::ostringstream os;
    os << "RSAO: needs a first-order B-format RIR of 4 channels (" << toString(format)
       << "), got " << channels << "; an omnidirectional RIR has no directions to estimate";
    throw InputError(os.str());
  }
  AudioBuffer first = input;
  first.channels.resize(4);
  const std::string doubt = checkAmbisonicFormat(first, format);
  if (!doubt.empty()) warnings.push_back(doubt);
  AudioBuffer ambix = toAmbix(first, format);
  if (ambix.sample_rate_hz != kFs) {
    std::ostringstream os;
    os << "input at " << ambix.sample_rate_hz << " Hz resampled to 48000 Hz";
    warnings.push_back(os.str());
    ambix = resample(ambix, kFs);
  }
  const auto& w = ambix.channels[kAcnW];
  if (std::none_of(w.begin(), w.end(), [](float v) { return v != 0.0f; })) {
    throw InputError("RSAO: the W channel is silent, every sample is zero; check the recording and the channel order");
  }
  return ambix;
}

// Peak power within 1 ms of the onset over the mean power of the span after it, in dB.
double directProminenceDb(const std::vector<float>& w, std::size_t onset) {
  const auto ms = static_cast<std::size_t>(kFs / 1000.0);
  double peak = 0.0;
  for (std::size_t n = onset; n < std::min(w.size(), onset + ms); ++n) peak = std::max(peak, double(w[n]) * w[n]);
  const std::size_t from = onset + static_cast<std::size_t>(kProminenceGapS * kFs);
  const std::size_t to = std::min(w.size(), from + static_cast<std::size_t>(kProminenceSpanS * kFs));
  if (from >= to) return 300.0;  // nothing after it: the direct sound is all there is
  double sum = 0.0;
  for (std::size_t n = from; n < to; ++n) sum += double(w[n]) * w[n];
  const double mean = sum / static_cast<double>(to - from);
  return mean > 0.0 ? 10.0 * std::log10(peak / mean) : 300.0;
}

std::string seconds(double s) {
  std::ostringstream os;
  os.precision(4);
  os << s << " s";
  return os.str();
}

// The late part needs kMinLateS of signal after the mixing time, which comes at or after
// `from_s` (`what` names that time).
void requireLateSpan(double duration_s, double from_s, const std::string& what) {
  if (duration_s >= from_s + kMinLateS) return;
  throw InputError("RSAO: the impulse response is too short: " + seconds(duration_s) + ", " + what + " at " +
                   seconds(from_s) + "; the late reverb needs at least " + seconds(kMinLateS) +
                   " after the mixing time");
}

}  // namespace

void validateRsaoOptions(const RsaoOptions& options) {
  EarlyReflectionOptions early = options.early;
  early.mixing_time_s.reset();
  validateEarlyReflectionOptions(early);
  if (options.mixing_time_s && !(std::isfinite(*options.mixing_time_s) && *options.mixing_time_s > 0.0)) {
    throw InputError("RSAO: mixing_time_s = " + std::to_string(*options.mixing_time_s) +
                     "; give a positive time from the first sample, or leave it to the echo density");
  }
  if (!std::isfinite(options.min_direct_prominence_db)) {
    throw InputError("RSAO: min_direct_prominence_db must be finite, e.g. 15");
  }
}

Rsao estimateRsao(const AudioBuffer& bformat, AmbisonicFormat format, const RsaoOptions& options) {
  validateRsaoOptions(options);
  Rsao rsao;
  const AudioBuffer ambix = firstOrderAmbix48k(bformat, format, rsao.warnings);
  const std::vector<float>& w = ambix.channels[kAcnW];
  rsao.sample_rate_hz = kFs;
  rsao.duration_s = ambix.durationS();

  const std::size_t onset = findDirectSoundOnset(w, options.early.direct_onset_threshold_db);
  const double prominence = directProminenceDb(w, onset);
  if (prominence < options.min_direct_prominence_db) {
    std::ostringstream os;
    os.precision(3);
    os << "RSAO: no clear direct sound: the strongest early peak (at " << onset / kFs << " s) is only " << prominence
       << " dB above the mean level of the 50 ms after it (at least " << options.min_direct_prominence_db
       << " dB expected); is this a room impulse response, with the source in line of sight?";
    throw InputError(os.str());
  }
  const std::size_t clipped = findClippedRun(w, 0, options.late.clip_run_samples);
  if (clipped < w.size()) {
    rsao.warnings.push_back("clipped input: a flat top of full-peak samples at " + seconds(clipped / kFs) +
                            "; levels and filters of what clipped are too low, re-measure with less gain");
  }

  const double onset_s = static_cast<double>(onset) / kFs;
  // Checked before the mixing time too (which cannot precede the direct sound): the echo
  // density of a response this short would fail with a message about noise instead.
  requireLateSpan(rsao.duration_s, onset_s, "the direct sound");
  double mixing_time_s = 0.0;
  if (options.mixing_time_s) {
    mixing_time_s = *options.mixing_time_s;
    if (mixing_time_s <= onset_s) {
      throw InputError("RSAO: the fixed mixing time " + seconds(mixing_time_s) + " is not after the direct sound (" +
                       seconds(onset_s) + ")");
    }
  } else {
    const MixingTimeResult mixing =
        estimateMixingTime(echoDensityProfile(w, kFs, options.echo_density), onset_s, options.mixing);
    mixing_time_s = mixing.mixing_time_s;
    if (!mixing.reached_threshold) rsao.warnings.push_back("mixing time: " + mixing.note);
  }
  requireLateSpan(rsao.duration_s, mixing_time_s, "the mixing time");

  EarlyReflectionOptions early = options.early;
  early.mixing_time_s = mixing_time_s;
  rsao.reflections = estimateEarlyReflections(ambix, early);
  const double first_reflection_s = rsao.reflections.size() > 1 ? rsao.reflections[1].time_of_arrival_s
                                                                 : rsao.reflections.front().time_of_arrival_s;
  rsao.late = estimateLateReverb(w, std::min(first_reflection_s, mixing_time_s), mixing_time_s, options.late);
  if (options.fit_onset_ramps) fitOnsetRamps(w, rsao, {options.early.analysis_window_s});
  return rsao;
}

}  // namespace room_reverb::core
