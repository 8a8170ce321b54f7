#pragma once
// A room-like RSAO late part with known truth, for the tests of everything that renders one.
#include <vector>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::test {

// T60 [s] and level (RMS at the mixing time) per octave band 63 Hz .. 16 kHz.
const std::vector<double>& roomLikeT60s();
const std::vector<double>& roomLikeLevels();

// An Rsao of `duration_s` with no reflections and the late part above: onset 10 ms,
// mixing time 60 ms (attack 50 ms), the paper's linear ramp.
core::Rsao roomLikeLateRsao(double duration_s);

}  // namespace room_reverb::test
