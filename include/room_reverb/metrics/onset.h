#pragma once
#include <cstddef>
#include <vector>

namespace room_reverb::core {

// Direct-sound onset after ISO 3382-1 (annex A): the first sample whose squared value comes
// within `threshold_db` (20 dB by the standard) of the squared peak. Throws InputError for
// an empty or all-zero signal.
std::size_t findDirectSoundOnset(const std::vector<float>& rir, double threshold_db = 20.0);

}  // namespace room_reverb::core
