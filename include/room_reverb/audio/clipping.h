#pragma once
// Detection of clipping: the flat tops a converter or an amplifier leaves when the signal
// exceeds its range.
#include <cstddef>
#include <vector>

namespace room_reverb::core {

// First sample (at or after `from`) of a run of `run` or more samples at the signal's peak
// magnitude, or x.size() when there is none. A smooth waveform's samples near its crest
// differ in the 5th digit even at 63 Hz (48 kHz), so the relative tolerance is far tighter
// than that; runs shorter than 2 are not a flat top.
std::size_t findClippedRun(const std::vector<float>& x, std::size_t from, int run);

}  // namespace room_reverb::core
