#pragma once
// Sample-rate conversion with libsamplerate's best sinc converter.
#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

// Returns the buffer at `target_rate_hz` (a copy when the rate already matches). The
// output has round(frames * target / source) frames, time-aligned with the input.
AudioBuffer resample(const AudioBuffer& buffer, double target_rate_hz);

// resample() to the internal 48 kHz rate.
inline AudioBuffer toInternalRate(const AudioBuffer& buffer) {
  return resample(buffer, kInternalSampleRateHz);
}

}  // namespace room_reverb::core
