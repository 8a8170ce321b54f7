#include "room_reverb/rsao/rsao_render_input.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/late_envelope.h"
#include "room_reverb/rsao/reflection_tap.h"

namespace room_reverb::core {
namespace {

constexpr double kMaxDurationS = 60.0;

bool finiteNonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

void checkRsao(const Rsao& r, const std::string& context) {
  for (std::size_t k = 0; k < r.reflections.size(); ++k) {
    const EarlyReflection& e = r.reflections[k];
    if (!finiteNonNegative(e.time_of_arrival_s) || !finiteNonNegative(e.level) || !std::isfinite(e.azimuth_rad) ||
        !std::isfinite(e.elevation_rad)) {
      throw InputError(context + ": " + reflectionName(k) +
                       " needs a finite, non-negative time of arrival and level and a finite direction");
    }
  }
  const LateReverb& late = r.late;
  if (late.bands.empty()) return;
  if (late.bands.size() != static_cast<std::size_t>(kOctaveBandCount)) {
    throw InputError(context + ": the late reverb has " + std::to_string(late.bands.size()) +
                     " bands; it needs the nine octave bands 63 Hz .. 16 kHz");
  }
  if (!finiteNonNegative(late.onset_s) || !finiteNonNegative(late.mixing_time_s) || late.onset_s > late.mixing_time_s) {
    throw InputError(context + ": the late onset must be finite, non-negative and no later than the mixing time");
  }
  for (const LateReverbBand& band : late.bands) {
    if (!(std::isfinite(band.decay_constant_per_s) && band.decay_constant_per_s > 0.0) || !finiteNonNegative(band.level) ||
        !finiteNonNegative(band.onset_level)) {
      throw InputError(context + ": the late band at " + std::to_string(static_cast<int>(std::lround(band.center_hz))) +
                       " Hz needs a positive decay constant and a non-negative level and onset level");
    }
    if (!slopesWellFormed(band)) {
      throw InputError(context + ": the late band at " + std::to_string(static_cast<int>(std::lround(band.center_hz))) +
                       " Hz has two slopes: second_share must lie in (0, 1) and both decay constants be positive");
    }
  }
}

double defaultDuration(const Rsao& r, const ResynthesisOptions& o) {
  if (r.duration_s > 0.0) return r.duration_s;
  double end = 0.0;
  for (const EarlyReflection& e : r.reflections) end = std::max(end, e.time_of_arrival_s + o.reflection_response_s);
  for (const LateReverbBand& band : r.late.bands) {
    end = std::max(end, r.late.mixing_time_s + lateDecayLengthS(band));  // 60 dB of the band's decay
  }
  return end;
}

}  // namespace

void checkRenderInput(const Rsao& rsao, const ResynthesisOptions& options, const std::string& context) {
  checkRsao(rsao, context);
  if (!(options.analysis_window_s > 0.0 && options.reflection_response_s >= 0.0 && options.match_bandwidths > 0.0 &&
        options.match_passes >= 0)) {
    throw InputError(context + ": analysis_window_s and match_bandwidths must be positive, match_passes not negative");
  }
}

std::size_t renderFrameCount(const Rsao& rsao, const ResynthesisOptions& options, const std::string& context) {
  const double duration = options.duration_s > 0.0 ? options.duration_s : defaultDuration(rsao, options);
  if (!(duration > 0.0 && duration <= kMaxDurationS)) {
    char text[64];
    std::snprintf(text, sizeof text, "%.4g", duration);
    throw InputError(context + ": the output would last " + text + " s; give duration_s in (0, 60]");
  }
  return static_cast<std::size_t>(std::lround(duration * kInternalSampleRateHz));
}

}  // namespace room_reverb::core
