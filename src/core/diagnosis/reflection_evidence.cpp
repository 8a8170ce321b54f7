#include "room_reverb/diagnosis/reflection_evidence.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/diagnosis/model_evaluation.h"

namespace room_reverb::core {

double reflectionMismatchJnd(const std::vector<RelativeReflection>& measured, const std::vector<SpecularPath>& paths,
                             const MeasurementPair& pair, const AcousticScene& scene, double speed_of_sound_m_s) {
  double error_jnd = 0.0;
  for (const UnexplainedReflection& r : unexplainedReflections(measured, paths, pair, scene, speed_of_sound_m_s,
                                                               ExplanationRule::kAudibleOrMerged)) {
    error_jnd += std::min(kTermCapJnd, r.level_db - kStrongReflectionLevelDb);
  }
  return error_jnd;
}

}  // namespace room_reverb::core
