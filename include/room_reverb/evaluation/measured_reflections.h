#pragma once
// The strong early reflections of a measured first-order B-format RIR, relative to its
// direct sound (time, level, direction): the reflections a comparison reports and a
// diagnosis must explain.
#include <optional>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/evaluation/reflection_matching.h"

namespace room_reverb::core {

// A reflection is strong when it comes within 30 ms of the direct sound (later ones crowd
// too densely to tell apart) and at most 14 dB below it.
constexpr double kStrongReflectionLatestS = 0.030;
constexpr double kStrongReflectionLevelDb = -14.0;

// The strong ones among reflections relative to their direct sound.
std::vector<RelativeReflection> strongReflections(const std::vector<RelativeReflection>& reflections);

// The reflections of a first-order AmbiX RIR at 48 kHz, relative to its direct sound, up to
// 34 ms after it and down to 24 dB below it (the strong ones and some margin, so that a
// strong reflection near either limit is not lost to a rounding of its level). nullopt
// without a clear direct sound or with fewer than four channels.
std::optional<std::vector<RelativeReflection>> reflectionEvidence(const AudioBuffer& ambix_48k);

}  // namespace room_reverb::core
