#pragma once
// Conversions between the project's audio messages and the core's audio types.
#include <room_reverb/AudioBuffer.h>
#include <room_reverb/ImpulseResponse.h>

#include <string>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::ros_bridge {

enum class NonFiniteSamples {
  kReject,  // an impulse response with a NaN is corrupt: refuse it
  kKeep,    // a live source stream: the consumer zeroes and counts them, the stream goes on
};

// Throws core::InputError when the message is inconsistent (no channels, a sample count
// that is not a multiple of the channel count, channel_count disagreeing with the data),
// and, unless `non_finite` is kKeep, when a sample is NaN or infinite or the rate is out
// of range.
core::AudioBuffer fromMessage(const room_reverb::AudioBuffer& msg, NonFiniteSamples non_finite = NonFiniteSamples::kReject);
room_reverb::AudioBuffer toMessage(const core::AudioBuffer& buffer, const std::string& channel_layout);

}  // namespace room_reverb::ros_bridge
