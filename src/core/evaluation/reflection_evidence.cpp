#include "room_reverb/evaluation/reflection_evidence.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/error.h"
#include "room_reverb/evaluation/model_evaluation.h"
#include "room_reverb/rsao/early_reflections.h"

namespace room_reverb::core {
namespace {

constexpr double kMarginDb = 10.0;
constexpr double kWindowMarginS = 0.004;

}  // namespace

std::optional<std::vector<RelativeReflection>> reflectionEvidence(const AudioBuffer& ambix_48k) {
  if (ambix_48k.channelCount() < 4) return std::nullopt;
  EarlyReflectionOptions options;
  options.default_early_duration_s = kStrongReflectionLatestS + kWindowMarginS;
  options.selection = ReflectionSelection::kAboveLevelThreshold;
  options.level_threshold_db = kStrongReflectionLevelDb - kMarginDb;
  options.max_reflections = 60;
  try {
    Rsao early;
    early.reflections = estimateEarlyReflections(ambix_48k, options);
    return relativeReflections(early);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

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
