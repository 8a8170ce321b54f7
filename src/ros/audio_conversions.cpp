#include "room_reverb/ros/audio_conversions.h"

#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {

core::AudioBuffer fromMessage(const room_reverb::AudioBuffer& msg, NonFiniteSamples non_finite) {
  if (msg.channel_count == 0) throw core::InputError("audio message has channel_count 0");
  if (msg.samples.empty()) throw core::InputError("audio message holds no samples");
  if (msg.samples.size() % msg.channel_count != 0) {
    std::ostringstream os;
    os << "audio message has " << msg.samples.size() << " samples, not a multiple of its "
       << msg.channel_count << " channels";
    throw core::InputError(os.str());
  }
  core::AudioBuffer buffer = core::deinterleave(msg.samples, msg.channel_count, msg.sample_rate_hz);
  if (non_finite == NonFiniteSamples::kReject) core::validateAudioBuffer(buffer, "audio message");
  return buffer;
}

room_reverb::AudioBuffer toMessage(const core::AudioBuffer& buffer, const std::string& channel_layout) {
  room_reverb::AudioBuffer msg;
  msg.sample_rate_hz = buffer.sample_rate_hz;
  msg.channel_count = static_cast<uint32_t>(buffer.channelCount());
  msg.channel_layout = channel_layout;
  msg.samples = core::interleave(buffer);
  return msg;
}

}  // namespace room_reverb::ros_bridge
