#pragma once
// Energy decay curves per octave band for the figures of a comparison and a diagnosis.
#include <cstddef>
#include <vector>

namespace room_reverb::core {

// Times 0, step_s, 2 step_s, ... up to length_s: the x axis of a decay-curve figure.
std::vector<double> decayCurveTimes(double step_s, double length_s);

// Schroeder decay curve of one octave band of an omni response, in dB, at
// decayCurveTimes(step_s, length_s) from the onset (NaN past the point the curve can be
// trusted: Lundeby's crosspoint).
std::vector<double> bandDecayCurveDb(const std::vector<float>& omni, double sample_rate_hz, std::size_t onset_sample,
                                     double band_hz, double step_s, double length_s);

}  // namespace room_reverb::core
