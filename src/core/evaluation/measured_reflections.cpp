#include "room_reverb/evaluation/measured_reflections.h"

#include "room_reverb/common/error.h"
#include "room_reverb/rsao/early_reflections.h"

namespace room_reverb::core {
namespace {

constexpr double kMarginDb = 10.0;
constexpr double kWindowMarginS = 0.004;

}  // namespace

std::vector<RelativeReflection> strongReflections(const std::vector<RelativeReflection>& reflections) {
  std::vector<RelativeReflection> strong;
  for (const RelativeReflection& r : reflections) {
    if (r.delay_s > 0.0 && r.delay_s <= kStrongReflectionLatestS && r.level_db >= kStrongReflectionLevelDb) strong.push_back(r);
  }
  return strong;
}

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

}  // namespace room_reverb::core
