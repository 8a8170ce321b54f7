#pragma once
// The binaural room responses (BRIRs) behind a MUSHRA plan's conditions: for every room
// and condition, what a dry source is convolved with to become that page's stimulus. Each
// comes from the project's offline rendering path, the same as `room_reverb render`:
//
//   reference    measured B-format RIR -> ambixRoomResponse -> binauralRoomResponse
//                (rotation for a head facing +x, then the plan's decoder)
//   rsao         estimateRsao(measured RIR) -> renderRsaoBinaural (seeded late noise)
//   fast         simulateRoom(room model, fast) -> binauralRoomResponse
//   accurate     simulateRoom(room model, accurate, plan's rays and seed) -> binauralRoomResponse
//   wrong_room   the reference BRIR of the room named by wrong_room_of
//   lowpass_3k5  the reference BRIR, with the instruction to low-pass the stimulus at
//                3.5 kHz (lowpass_filter.h, the filter's delay taken out so the anchor
//                lines up with the reference). The stimulus is filtered, not the response:
//                convolution commutes, but a response's direct sound sits closer to its
//                start than the filter's pre-ringing reaches, and cutting that ringing off
//                would spread a broadband error over the whole stimulus; at the start of a
//                stimulus the fade-in covers what is cut.
//
// Responses are made once and shared (a room's reference serves its own reference and
// lowpass_3k5 and another room's wrong_room); one HRTF set, one decoder per order and one
// diffuse-field spectrum serve every room.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/listening/mushra_plan.h"

namespace room_reverb::core {

// The cutoff of ITU-R BS.1534-3's low anchor.
constexpr double kLowAnchorCutoffHz = 3500.0;

struct MushraConditionResponse {
  AudioBuffer brir;                // left, right, 48 kHz
  double stimulus_lowpass_hz = 0;  // > 0: low-pass the rendered stimulus at this cutoff
};

struct MushraRoomResponses {
  // (room, condition) -> its response.
  std::map<std::pair<std::string, std::string>, MushraConditionResponse> responses;
  // What was changed or doubted on the way (resampling, HRTF notes, RSAO warnings, leaked
  // rays), each line naming its room, for the tool to print.
  std::vector<std::string> notes;

  const MushraConditionResponse& at(const std::string& room, const std::string& condition) const;
};

// Every room's response for every condition of the plan. InputError (naming the room and
// condition) for whatever the renderers refuse: an unreadable RIR or HRTF set, a RIR with
// no clear direct sound for the RSAO, a source or listener outside the room model...
MushraRoomResponses renderMushraRoomResponses(const MushraPlan& plan);

}  // namespace room_reverb::core
