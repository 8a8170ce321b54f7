#include "room_reverb/audio/channel_mix.h"

namespace room_reverb::core {

AudioBuffer mixToMono(const AudioBuffer& buffer) {
  if (buffer.channelCount() <= 1) return buffer;
  AudioBuffer mono = makeSilentBuffer(1, buffer.frameCount(), buffer.sample_rate_hz);
  const float scale = 1.0f / static_cast<float>(buffer.channelCount());
  for (const auto& channel : buffer.channels) {
    for (std::size_t n = 0; n < channel.size(); ++n) mono.channels[0][n] += scale * channel[n];
  }
  return mono;
}

}  // namespace room_reverb::core
