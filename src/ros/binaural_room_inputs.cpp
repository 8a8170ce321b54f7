#include "room_reverb/ros/binaural_room_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "room_reverb/audio/audio_file.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/common/error.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/room_conversions.h"
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

StreamRoom walkableSimulatedRoom(const room_reverb::RoomScene& scene, const room_reverb::SimulateRoom::Response& simulated,
                                 const core::MaterialLibrary& library, const std::string& description) {
  const core::AudioBuffer whole = fromMessage(simulated.impulse_response.audio);
  if (simulated.late_impulse_response.audio.samples.empty()) {
    throw core::InputError("the simulator sent no late part (an older room_simulator?)");
  }
  core::AudioBuffer late = fromMessage(simulated.late_impulse_response.audio);
  const core::RoomModel model = fromMessage(scene.room);
  core::SimulationSettings settings;
  settings.image_source_order = simulated.image_source_order;
  settings.ambisonic_order = core::ambixOrder(whole);
  settings.duration_s = whole.durationS();
  settings.air = model.air;
  const Eigen::Vector3d source(scene.source.x, scene.source.y, scene.source.z);
  const Eigen::Vector3d listener(scene.listener.x, scene.listener.y, scene.listener.z);
  auto walk = std::make_shared<const core::SimulatedWalk>(core::roomModelToScene(model, library), source, listener,
                                                           settings, std::move(late));
  StreamRoom room;
  room.early = walk->earlyAt(listener);
  // The image sources computed here and the simulator's late part add up to its response
  // only if both used the same materials and settings.
  const core::AudioBuffer heard = walk->responseWith(room.early);
  if (heard.frameCount() != whole.frameCount()) {
    throw core::InputError("the simulator's late part and its response differ in length");
  }
  double energy = 0.0, residual = 0.0;
  for (std::size_t c = 0; c < whole.channelCount(); ++c) {
    for (std::size_t n = 0; n < whole.frameCount(); ++n) {
      const double difference = static_cast<double>(whole.channels[c][n]) - heard.channels[c][n];
      energy += static_cast<double>(whole.channels[c][n]) * whole.channels[c][n];
      residual += difference * difference;
    }
  }
  const double residual_db = 10.0 * std::log10(std::max(residual, 1e-30) / std::max(energy, 1e-30));
  if (residual_db > -40.0) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "the image sources computed here differ from the simulator's by %.1f dB (are its materials this node's?)",
                  residual_db);
    throw core::InputError(text);
  }
  room.ambix = walk->late();
  room.simulated_walk = std::move(walk);
  room.description = describe(description + ", walkable", whole);
  return room;
}

StreamRoom roomFromRsao(const core::Rsao& rsao, std::uint32_t seed, const std::string& what,
                        const std::shared_ptr<const core::RoomModel>& walkable) {
  core::ResynthesisOptions options;
  options.seed = seed;
  StreamRoom room;
  std::string kind = what + ", " + std::to_string(rsao.reflections.size()) + " reflections";
  core::Rsao played = rsao;
  if (walkable) {
    room.translation = std::make_shared<const core::ListenerTranslation>(rsao, walkable->rig_position_m,
                                                                         walkable->rig_rotation, *walkable);
    room.room_model = walkable;
    options.include_early = false;
    played.late = room.translation->late();  // its course yields to the completed reflections
    kind += ", walkable";
  }
  room.ambix = core::resynthesizeRsao(played, options);
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
