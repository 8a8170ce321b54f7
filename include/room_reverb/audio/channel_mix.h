#pragma once
#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

// The mean of the channels, as one channel (a mono buffer is returned as it is). The mean,
// not the sum, so that a stereo file of one voice keeps its level.
AudioBuffer mixToMono(const AudioBuffer& buffer);

}  // namespace room_reverb::core
