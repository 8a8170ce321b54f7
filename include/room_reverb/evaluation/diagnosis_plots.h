#pragma once
// The figures of a diagnosis: energy decay curves per octave band, measured against the
// model before and after the named causes (decay_curves.png), and the mean signed error
// per band and parameter before and after (error_per_band.png).
#include <string>
#include <vector>

#include "room_reverb/evaluation/diagnosis.h"

namespace room_reverb::core {

// Writes the figures into `directory` and returns their paths.
std::vector<std::string> writeDiagnosisPlots(const Diagnosis& diagnosis, const MeasuredEvidence& evidence,
                                             const std::string& directory);

// Schroeder decay curve of one octave band of an omni response, in dB, sampled every
// `step_s` from the onset up to `length_s` (NaN past the point the curve can be trusted).
std::vector<double> bandDecayCurveDb(const std::vector<float>& omni, double sample_rate_hz, std::size_t onset_sample,
                                     double band_hz, double step_s, double length_s);

}  // namespace room_reverb::core
