#include "room_reverb/ros/binaural_room_inputs.h"

#include <cstdio>

#include "room_reverb/audio/audio_file.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/common/error.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/rsao_conversions.h"
#include "room_reverb/rsao/rsao_resynthesis.h"
#include "room_reverb/rsao/rsao_yaml.h"

namespace room_reverb::ros_bridge {
namespace {

std::string describe(const std::string& what, const core::AudioBuffer& ambix) {
  char text[160];
  std::snprintf(text, sizeof text, "%s (order %d, %.2f s)", what.c_str(), core::ambixOrder(ambix), ambix.durationS());
  return text;
}

}  // namespace

StreamRoom roomFromRsao(const core::Rsao& rsao, std::uint32_t seed, const std::string& what,
                        const std::shared_ptr<const core::RoomModel>& walkable) {
  core::ResynthesisOptions options;
  options.seed = seed;
  StreamRoom room;
  std::string kind = what + ", " + std::to_string(rsao.reflections.size()) + " reflections";
  if (walkable) {
    room.translation = std::make_shared<const core::ListenerTranslation>(rsao, walkable->rig_position_m,
                                                                         walkable->rig_rotation, *walkable);
    room.room_model = walkable;
    options.include_early = false;
    kind += ", walkable";
  }
  room.ambix = core::resynthesizeRsao(rsao, options);
  room.description = describe(kind, room.ambix);
  return room;
}

StreamRoom roomFromImpulseResponse(const room_reverb::ImpulseResponse& message) {
  StreamRoom room;
  const std::string& layout = message.audio.channel_layout;
  room.ambix = core::ambixRoomResponse(fromMessage(message.audio), layout, room.notes);
  room.description = describe("impulse_response " + layout, room.ambix);
  return room;
}

StreamRoom roomFromRsao(const room_reverb::Rsao& message, std::uint32_t seed,
                        const std::shared_ptr<const core::RoomModel>& walkable) {
  return roomFromRsao(fromMessage(message), seed, "rsao", walkable);
}

StreamRoom roomFromFile(const std::string& path, const std::string& format, std::uint32_t seed,
                        const std::shared_ptr<const core::RoomModel>& walkable) {
  if (format == "rsao") return roomFromRsao(core::loadRsaoYaml(path), seed, "rsao " + path, walkable);
  StreamRoom room;
  room.ambix = core::ambixRoomResponse(core::readAudioFile(path), format, room.notes);
  room.description = describe(format + " " + path, room.ambix);
  return room;
}

}  // namespace room_reverb::ros_bridge
