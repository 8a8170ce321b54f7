#pragma once
// Joining two versions of one response at a crossover frequency: below it from one (e.g.
// a modal synthesis of the low band), above it from the other (the ray-traced response).
//
// The split is zero-phase and amplitude-complementary (the low-pass H and the high-pass
// 1 - H sum to one), so a response joined with itself comes back unchanged and nothing
// is delayed against the rest. H falls from 1 to 0 over `width_octaves` centred on the
// crossover as cos^2 on a log-frequency axis (half amplitude at the crossover).
#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

// `low` below the crossover, `high` above it, channel by channel: the result has `high`'s
// channels and length; channels `low` lacks stay as in `high`, and a shorter `low` counts
// as zero past its end. InputError for different sample rates, a crossover outside
// (0, Nyquist) or a width that is not positive.
AudioBuffer joinAtCrossover(const AudioBuffer& low, const AudioBuffer& high, double crossover_hz,
                            double width_octaves = 1.0);

// The low-pass H at `frequency_hz`.
double crossoverLowGain(double frequency_hz, double crossover_hz, double width_octaves = 1.0);

}  // namespace room_reverb::core
