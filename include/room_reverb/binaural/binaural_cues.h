#pragma once
// Interaural time and level differences of a left/right impulse-response pair, the cues
// by which binaural renderings are compared with each other (docs/binaural_decoders.md).
#include <vector>

#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/binaural/hrtf_set.h"

namespace room_reverb::core {

// Below about 1.5 kHz the ITD (of the fine structure) dominates lateralisation; above it
// the ILD does (the duplex theory; Wightman & Kistler, JASA 91(3), 1992).
constexpr double kItdMaxFrequencyHz = 1500.0;

// Arrival at the right ear minus arrival at the left, in seconds (positive: source on the
// left): the lag of the peak of the interaural cross-correlation of the pair low-passed
// at `max_frequency_hz`, the "IACC" estimator of Katz & Noisternig (JASA 135(6), 2014),
// searched within +-1 ms at 1/16-sample resolution with a parabolic peak fit.
// InputError for an empty pair or ears of different lengths.
double interauralTimeDifferenceS(const Hrir& pair, double sample_rate_hz,
                                 double max_frequency_hz = kItdMaxFrequencyHz);

// 10 log10(E_left / E_right) per band, in dB (positive: louder at the left ear), the band
// energies read from the pair's spectra through the power-complementary band filters of
// BandFilterBank. Bands at or above Nyquist give 0.
std::vector<double> interauralLevelDifferencesDb(const Hrir& pair, double sample_rate_hz,
                                                 const std::vector<FrequencyBand>& bands);

}  // namespace room_reverb::core
