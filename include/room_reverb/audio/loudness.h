#pragma once
// Programme loudness after ITU-R BS.1770-4 (K-weighting, 400 ms blocks overlapping by 75 %,
// absolute gate at -70 LUFS and relative gate 10 LU below the ungated mean), measured with
// libebur128, the reference implementation broadcasters use (EBU R 128), rather than
// written again here.
//
// Binaural signals are measured as a stereo pair (left, right), as listening-test practice
// does: BS.1770 has no binaural weighting, and its stereo sum is what matching by loudness
// needs, since every stimulus of a test is measured the same way.
#include <string>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

// The shortest signal that has an integrated loudness: one 400 ms gating block.
constexpr double kLoudnessBlockS = 0.4;

// Integrated loudness (LUFS) of a mono or stereo buffer (channel 0 left, 1 right), at any
// rate the project accepts. `what` names the signal in messages ("stimulus studio/speech/
// rsao"). InputError for an invalid buffer, more than two channels, a signal shorter than
// one gating block, or silence (no block above the absolute gate: the loudness would be
// -infinity and no gain could match it).
double integratedLoudnessLufs(const AudioBuffer& audio, const std::string& what);

// The linear gain that takes a signal of `measured_lufs` to `target_lufs`. Loudness scales
// exactly with gain (the gates are relative or far below), so one multiplication matches.
// InputError unless both values are finite.
double loudnessMatchingGain(double measured_lufs, double target_lufs);

}  // namespace room_reverb::core
