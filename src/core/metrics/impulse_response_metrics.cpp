#include "room_reverb/metrics/impulse_response_metrics.h"

#include <sstream>

#include "room_reverb/audio/resample.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

MetricsReport analyseImpulseResponse(const AudioBuffer& rir, int channel, MetricsOptions options) {
  validateAudioBuffer(rir, "impulse response");
  if (channel < 0 || static_cast<std::size_t>(channel) >= rir.channelCount()) {
    std::ostringstream os;
    os << "channel " << channel << " does not exist; the impulse response has "
       << rir.channelCount() << " channel(s), numbered from 0";
    throw InputError(os.str());
  }
  AudioBuffer mono;
  mono.sample_rate_hz = rir.sample_rate_hz;
  mono.channels.push_back(rir.channels[static_cast<std::size_t>(channel)]);
  // Check length and silence before resampling, so the error names the input as given.
  if (mono.frameCount() < static_cast<std::size_t>(0.010 * rir.sample_rate_hz) + 1) {
    std::ostringstream os;
    os << "the impulse response is " << mono.frameCount()
       << " samples long; at least 10 ms is needed";
    throw InputError(os.str());
  }
  const double original_nyquist = 0.5 * rir.sample_rate_hz;
  if (options.recorded_bandwidth_hz <= 0.0 || options.recorded_bandwidth_hz > original_nyquist) {
    options.recorded_bandwidth_hz = original_nyquist;
  }
  const AudioBuffer internal = toInternalRate(mono);
  return computeRoomAcousticParameters(internal.channels.front(), internal.sample_rate_hz, options);
}

}  // namespace room_reverb::core
