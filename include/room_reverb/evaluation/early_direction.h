#pragma once
// Where the early reflections come from, per octave band: the energy of a virtual cardioid
// steered along each of the room frame's six axis directions (+x, -x, +y, -y, +z, -z) over
// the early reflections of a first-order B-format response, in dB relative to the omni
// energy of the same window. In a box these are the six walls: a wall that absorbs more
// than the model says sends less of the early energy from its side, while the room's
// decay times, clarity and DRR (all omni) only see the absorption area it adds, and
// cannot tell that wall from another of the same area (docs/validation/diagnosis.md).
// Levels relative to the window's omni energy leave out what the early energy profile
// (early_energy.h) already scores, and the measurement's gain.
#include <array>
#include <cstddef>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

struct EarlyDirectionOptions {
  std::vector<double> bands_hz{500, 1000, 2000, 4000};  // octaves where a room's walls differ
  double start_s = 0.0025;  // after the direct sound (its window ends 1.5 ms after the onset)
  double end_s = 0.040;     // first- to about third-order reflections of a room
};

// The six steering directions, in this order: +x, -x, +y, -y, +z, -z (room frame).
constexpr std::size_t kEarlyDirections = 6;

struct EarlyDirectionProfile {
  std::vector<double> bands_hz;
  std::vector<std::array<double, kEarlyDirections>> level_db;  // [band][direction]
  bool empty() const { return level_db.empty(); }
};

// `ambix`: a first-order AmbiX buffer (ACN W, Y, Z, X; SN3D); `onset_sample`: the direct
// sound's onset. Bands at or above Nyquist, and bands with no energy in the window, are
// left out. InputError for fewer than four channels, a window that is empty or not after
// the direct sound, or a response that ends before the window does.
EarlyDirectionProfile earlyDirectionProfile(const AudioBuffer& ambix, std::size_t onset_sample,
                                            const EarlyDirectionOptions& options = {});

}  // namespace room_reverb::core
