#include "room_reverb/audio/loudness.h"

#include <ebur128.h>

#include <cmath>
#include <memory>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

struct StateDeleter {
  void operator()(ebur128_state* state) const { ebur128_destroy(&state); }
};

}  // namespace

double integratedLoudnessLufs(const AudioBuffer& audio, const std::string& what) {
  validateAudioBuffer(audio, what);
  const std::size_t channels = audio.channelCount();
  if (channels > 2) {
    throw InputError(what + ": loudness is measured on mono or stereo signals, this one has " +
                     std::to_string(channels) + " channels");
  }
  if (audio.durationS() < kLoudnessBlockS) {
    std::ostringstream os;
    os << what << ": " << audio.durationS() << " s is shorter than the " << kLoudnessBlockS
       << " s block over which BS.1770 measures loudness";
    throw InputError(os.str());
  }
  std::unique_ptr<ebur128_state, StateDeleter> state(
      ebur128_init(static_cast<unsigned>(channels), static_cast<unsigned long>(std::lround(audio.sample_rate_hz)),
                   EBUR128_MODE_I));
  if (!state) throw InputError(what + ": libebur128 could not measure this signal (sample rate or memory)");
  // libebur128 maps channel 0 to left and 1 to right by default; a mono signal is measured
  // as its one channel, as BS.1770 weights a single front channel.
  const std::vector<float> frames = interleave(audio);
  if (ebur128_add_frames_float(state.get(), frames.data(), audio.frameCount()) != EBUR128_SUCCESS) {
    throw InputError(what + ": libebur128 refused the samples");
  }
  double lufs = 0.0;
  if (ebur128_loudness_global(state.get(), &lufs) != EBUR128_SUCCESS) {
    throw InputError(what + ": libebur128 could not compute the integrated loudness");
  }
  if (!std::isfinite(lufs)) {
    throw InputError(what + ": silent (no 400 ms block above -70 LUFS), so it has no loudness to match");
  }
  return lufs;
}

double loudnessMatchingGain(double measured_lufs, double target_lufs) {
  if (!std::isfinite(measured_lufs) || !std::isfinite(target_lufs)) {
    throw InputError("loudness matching needs finite loudness values");
  }
  return std::pow(10.0, (target_lufs - measured_lufs) / 20.0);
}

}  // namespace room_reverb::core
