#pragma once
// Writing a diagnosis to a directory, as the tool and the evaluation node do:
// diagnosis.json, report.md, the corrected room model (extended_room.yaml, room models
// only) and the figures (decay curves measured against simulated before and after, error
// per band before and after).
#include <string>
#include <vector>

#include "room_reverb/diagnosis/diagnosis.h"

namespace room_reverb::core {

struct DiagnosisFiles {
  std::string json, report, extended_room;  // "" when not written
  std::vector<std::string> plots;
};

// Creates `directory` if needed; InputError when it cannot be written.
DiagnosisFiles writeDiagnosis(const Diagnosis& diagnosis, const RoomUnderTest& room, const MeasuredEvidence& evidence,
                              const std::string& directory);

}  // namespace room_reverb::core
