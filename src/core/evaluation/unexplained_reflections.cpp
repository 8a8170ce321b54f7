#include "room_reverb/evaluation/unexplained_reflections.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/directions.h"

namespace room_reverb::core {
namespace {

constexpr double kMatchTimeS = 0.0006;   // 20 cm of path: a model's wall errors, twice over
constexpr double kMatchAngleRad = 0.55;  // 30 degrees: the steered cardioid's spread on real rooms
constexpr double kWallClearanceM = 0.3;
constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

}  // namespace

std::vector<RelativeReflection> strongEarlyReflections(const Rsao& rsao) {
  std::vector<RelativeReflection> strong;
  for (const RelativeReflection& r : relativeReflections(rsao)) {
    if (r.delay_s > 0.0 && r.delay_s <= kStrongReflectionLatestS && r.level_db >= kStrongReflectionLevelDb) strong.push_back(r);
  }
  return strong;
}

bool explainedBySpecularPath(const std::vector<SpecularPath>& paths, const RelativeReflection& reflection) {
  if (paths.empty()) return false;
  const double direct = paths.front().delay_s;
  const Eigen::Vector3d arrival =
      unitVectorFromAngles(reflection.azimuth_deg * kRadiansPerDegree, reflection.elevation_deg * kRadiansPerDegree);
  for (const SpecularPath& p : paths) {
    if (p.order == 0) continue;
    if (std::abs((p.delay_s - direct) - reflection.delay_s) > kMatchTimeS) continue;
    if (std::acos(std::clamp(p.arrival_direction.dot(arrival), -1.0, 1.0)) <= kMatchAngleRad) return true;
  }
  return false;
}

std::vector<UnexplainedReflection> unexplainedReflections(const Rsao& rsao, const std::vector<SpecularPath>& paths,
                                                          const MeasurementPair& pair, const AcousticScene& scene,
                                                          double speed_of_sound_m_s) {
  std::vector<UnexplainedReflection> out;
  const Eigen::Vector3d S = pair.source_m, R = pair.receiver_m;
  const double direct_length = (S - R).norm();
  for (const RelativeReflection& r : strongEarlyReflections(rsao)) {
    if (explainedBySpecularPath(paths, r)) continue;
    const Eigen::Vector3d u = unitVectorFromAngles(r.azimuth_deg * kRadiansPerDegree, r.elevation_deg * kRadiansPerDegree);
    const double L = direct_length + speed_of_sound_m_s * r.delay_s;
    const double denominator = 2.0 * (L - u.dot(S - R));
    if (denominator <= 1e-6) continue;
    const Eigen::Vector3d P = R + (L * L - direct_length * direct_length) / denominator * u;
    if (!P.allFinite() || !scene.isInside(P) || scene.distanceToNearestSurface(P) < kWallClearanceM) continue;
    out.push_back({P, ((S - P).normalized() + (R - P).normalized()).normalized(), r.level_db});
  }
  return out;
}

}  // namespace room_reverb::core
