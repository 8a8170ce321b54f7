#pragma once
// The rooms the binaural_renderer can be given, each turned into what the stream plays: an
// AmbiX room response at 48 kHz (offline_render.h) and a one-line description.
#include <room_reverb/ImpulseResponse.h>
#include <room_reverb/RoomScene.h>
#include <room_reverb/Rsao.h>
#include <room_reverb/SimulateRoom.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/binaural/binaural_stream.h"
#include "room_reverb/acoustics/simulated_walk.h"
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/rsao/listener_translation.h"

namespace room_reverb::ros_bridge {

struct StreamRoom {
  core::AudioBuffer ambix;          // AmbiX, 48 kHz, order 0-3
  std::string description;          // e.g. "impulse_response fuma 2.0 s"
  std::vector<std::string> notes;   // resampling and the like, for the log
  // An RSAO in a room model the listener walks in (six degrees of freedom): its direct
  // sound and early reflections move with the listener as taps (listener_translation.h,
  // reflection_tap_bank.h), and `ambix` holds only its late part. Null otherwise.
  std::shared_ptr<const core::ListenerTranslation> translation;
  std::shared_ptr<const core::RoomModel> room_model;
  // A simulated room the listener walks in: its image-source part computed again where the
  // listener stands (simulated_walk.h), `ambix` its late part, `early` the image-source
  // part at the simulated listener position. Null otherwise.
  std::shared_ptr<const core::SimulatedWalk> simulated_walk;
  core::AudioBuffer early;
  // `ambix` and `early` transformed for the stream (BinauralStream::prepareRoom and
  // prepareEarlyResponse) by whoever offers the room, so the audio thread only swaps them in.
  core::PreparedResponse prepared, prepared_early;
};

// An ImpulseResponse message: its audio.channel_layout says the convention ("fuma",
// "ambix" or "mono"). InputError for another layout, a bad message or bad audio.
StreamRoom roomFromImpulseResponse(const room_reverb::ImpulseResponse& message);

// An RSAO, resynthesized as a first-order AmbiX response (rsao_resynthesis.h) with `seed`,
// so that head tracking can turn it like any other room. With `walkable` (the room model
// it was measured in, with the rig's pose), only its late part is resynthesized and the
// room carries the RSAO moved per listener position. InputError for an RSAO that cannot
// be rendered or placed in the model.
StreamRoom roomFromRsao(const core::Rsao& rsao, std::uint32_t seed, const std::string& what,
                        const std::shared_ptr<const core::RoomModel>& walkable = nullptr);
StreamRoom roomFromRsao(const room_reverb::Rsao& message, std::uint32_t seed,
                        const std::shared_ptr<const core::RoomModel>& walkable = nullptr);

// A RoomScene simulated by the room_simulator with late_part, made walkable: the scene built
// here from the same room model with `library`, the image sources at the scene's listener
// plus the simulator's late part must give back its whole response (within -40 dB: the
// simulator and this node must use the same materials), else InputError saying by how
// much they differ. `decoder_order`: the ambisonic order asked of the simulator.
StreamRoom walkableSimulatedRoom(const room_reverb::RoomScene& scene, const room_reverb::SimulateRoom::Response& simulated,
                                 const core::MaterialLibrary& library, const std::string& description);

// A file: a B-format or AmbiX RIR with `format` "fuma", "ambix" or "mono", or an RSAO YAML
// with format "rsao" (walkable as above). InputError for a missing or unreadable file or an
// unknown format.
StreamRoom roomFromFile(const std::string& path, const std::string& format, std::uint32_t seed,
                        const std::shared_ptr<const core::RoomModel>& walkable = nullptr);

}  // namespace room_reverb::ros_bridge
