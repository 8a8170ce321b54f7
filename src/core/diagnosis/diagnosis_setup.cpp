#include "room_reverb/diagnosis/diagnosis_setup.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

RoomUnderTest loadRoomUnderTest(const std::string& room_file, const std::string& mesh_file, UpAxis mesh_up,
                                const Measurements& measurements, bool no_air, const MaterialLibrary& library) {
  if (room_file.empty() == mesh_file.empty()) throw InputError("give exactly one room: a room model or a mesh");
  if (!room_file.empty()) {
    RoomModel model = loadRoomModel(room_file);
    if (no_air) model.air.enabled = false;
    return RoomUnderTest::fromRoomModel(model, library);
  }
  AirConditions air = measurements.air.value_or(AirConditions{});
  if (no_air) air.enabled = false;
  return RoomUnderTest::fromMesh(loadMesh(mesh_file, mesh_up), library, air);
}

double diagnosisDurationS(const MeasuredEvidence& evidence) {
  double longest = 0.0;
  for (const PairEvidence& pair : evidence.rirs) {
    for (const AcousticParameters& band : pair.metrics.bands) longest = std::max(longest, band.t20_s.value_or(0.0));
  }
  for (double t : evidence.table.t20_s) longest = std::max(longest, std::isfinite(t) ? t : 0.0);
  return std::clamp(1.1 * longest, 0.5, 3.0);
}

}  // namespace room_reverb::core
