#pragma once
// The extensions that act on a simulated response rather than on the scene
// (model_extension.h): the modal low band, then a coupled volume's decay. Shared by the
// evaluator, the fits that re-analyse responses already simulated, and the tests that
// plant these effects in a "measurement".
#include <cstdint>
#include <vector>

#include "room_reverb/acoustics/air_absorption.h"
#include "room_reverb/acoustics/room_modes.h"
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/diagnosis/model_extension.h"

namespace room_reverb::core {

// The coupled-volume extension applied to a response: a second exponential decay of white
// noise (seeded), starting at the direct sound.
void addCoupledDecay(std::vector<float>& omni, double sample_rate_hz, std::size_t onset_sample,
                     const CoupledDecay& decay, std::uint32_t seed);

// Where the modal band hands over to the rays in this scene: Schroeder's frequency from
// Eyring's mid-band T60 (mean of 500 Hz and 1 kHz, with the air) and the scene's volume.
double modalCrossoverHz(const AcousticScene& scene, const AirConditions& air);

// The room the modal extension uses for this scene (its box, with the air's speed of
// sound).
ModalRoom modalRoomFor(const AcousticScene& scene, const AirConditions& air);

// The extension's response effects on `response` (48 kHz; omni, or ambiX with the first
// order in channels 1-3): below `modes->crossover_hz` the room's modes replace the
// response (channels 0-3; higher orders are left alone), then the coupled decay is added
// to channel 0 from the direct sound on (`direct_delay_s`), with noise from `seed`.
// `modal_room` is needed only when the extension has modes. InputError for a pair
// outside the modal room's box.
void applyResponseExtensions(AudioBuffer& response, const ModelExtension& extension, const ModalRoom* modal_room,
                             const MeasurementPair& pair, double direct_delay_s, std::uint32_t seed);

}  // namespace room_reverb::core
