#pragma once
// Setting a diagnosis up from files, the same way for the diagnose tool and the
// evaluation node's ~diagnose service.
#include <string>

#include "room_reverb/acoustics/triangle_mesh.h"
#include "room_reverb/evaluation/measured_evidence.h"
#include "room_reverb/diagnosis/model_extension.h"

namespace room_reverb::core {

// The room to diagnose: a room-model YAML (its own air conditions) or a mesh (the
// measurement's air conditions, or ISO defaults); exactly one of the two paths is
// non-empty. `no_air` turns air absorption off, as a model without it. InputError when
// both or neither are given, or a file does not load.
RoomUnderTest loadRoomUnderTest(const std::string& room_file, const std::string& mesh_file, UpAxis mesh_up,
                                const Measurements& measurements, bool no_air, const MaterialLibrary& library);

// Response length for the diagnosis's simulations: 1.1 times the longest measured T20,
// within 0.5-3 s (long enough for T30 and the decay curves, short enough to stay fast).
double diagnosisDurationS(const MeasuredEvidence& evidence);

}  // namespace room_reverb::core
