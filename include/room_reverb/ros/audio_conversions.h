#pragma once
// Conversions between the project's audio messages and the core's audio types.
#include <room_reverb/AudioBuffer.h>
#include <room_reverb/ImpulseResponse.h>

#include <string>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::ros_bridge {

// Throws core::InputError when the message is inconsistent (no channels, a sample count
// that is not a multiple of the channel count, channel_count disagreeing with the data).
core::AudioBuffer fromMessage(const room_reverb::AudioBuffer& msg);
room_reverb::AudioBuffer toMessage(const core::AudioBuffer& buffer, const std::string& channel_layout);

}  // namespace room_reverb::ros_bridge
