#pragma once
// The figures of a diagnosis: energy decay curves per octave band, measured against the
// model before and after the named causes (decay_curves.png), and the mean signed error
// per band and parameter before and after (error_per_band.png).
#include <string>
#include <vector>

#include "room_reverb/diagnosis/diagnosis.h"

namespace room_reverb::core {

// Writes the figures into `directory` and returns their paths.
std::vector<std::string> writeDiagnosisPlots(const Diagnosis& diagnosis, const MeasuredEvidence& evidence,
                                             const std::string& directory);

}  // namespace room_reverb::core
