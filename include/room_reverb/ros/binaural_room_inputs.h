#pragma once
// The rooms the binaural_renderer can be given, each turned into what the stream plays: an
// AmbiX room response at 48 kHz (offline_render.h) and a one-line description.
#include <room_reverb/ImpulseResponse.h>
#include <room_reverb/Rsao.h>

#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::ros_bridge {

struct StreamRoom {
  core::AudioBuffer ambix;          // AmbiX, 48 kHz, order 0-3
  std::string description;          // e.g. "impulse_response fuma 2.0 s"
  std::vector<std::string> notes;   // resampling and the like, for the log
};

// An ImpulseResponse message: its audio.channel_layout says the convention ("fuma",
// "ambix" or "mono"). InputError for another layout, a bad message or bad audio.
StreamRoom roomFromImpulseResponse(const room_reverb::ImpulseResponse& message);

// An Rsao message, resynthesized as a first-order AmbiX response (rsao_resynthesis.h) with
// `seed`, so that head tracking can turn it like any other room.
StreamRoom roomFromRsao(const room_reverb::Rsao& message, std::uint32_t seed);

// A file: a B-format or AmbiX RIR with `format` "fuma", "ambix" or "mono", or an RSAO YAML
// with format "rsao". InputError for a missing or unreadable file or an unknown format.
StreamRoom roomFromFile(const std::string& path, const std::string& format, std::uint32_t seed);

}  // namespace room_reverb::ros_bridge
