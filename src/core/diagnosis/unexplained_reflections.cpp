#include "room_reverb/diagnosis/unexplained_reflections.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/directions.h"

namespace room_reverb::core {
namespace {

constexpr double kMatchTimeS = 0.0006;   // 20 cm of path: a model's wall errors, twice over
constexpr double kMatchAngleRad = 0.55;  // 30 degrees: the steered cardioid's spread on real rooms
constexpr double kWallClearanceM = 0.3;
// 10 dB below the strong threshold: the RSAO reads a reflection several dB above its
// path's own level (the diffuse energy in its window; a -15 dB path read at -4.6 dB).
constexpr double kExplainingPathLevelDb = kStrongReflectionLevelDb - 10.0;
constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

}  // namespace

bool pathMatchesReflection(const SpecularPath& path, double direct_delay_s, const RelativeReflection& reflection) {
  if (path.order == 0 || std::abs((path.delay_s - direct_delay_s) - reflection.delay_s) > kMatchTimeS) return false;
  const Eigen::Vector3d arrival =
      unitVectorFromAngles(reflection.azimuth_deg * kRadiansPerDegree, reflection.elevation_deg * kRadiansPerDegree);
  return std::acos(std::clamp(path.arrival_direction.dot(arrival), -1.0, 1.0)) <= kMatchAngleRad;
}

double pathLevelDb(const SpecularPath& path, const SpecularPath& direct) {
  double e = 0.0, e0 = 0.0;
  for (std::size_t b = 3; b <= 6; ++b) {  // 500 Hz - 4 kHz
    e += path.pressure_gain[b] * path.pressure_gain[b];
    e0 += direct.pressure_gain[b] * direct.pressure_gain[b];
  }
  return 10.0 * std::log10(std::max(e, 1e-30) / std::max(e0, 1e-30));
}

bool explainedBySpecularPath(const std::vector<SpecularPath>& paths, const RelativeReflection& reflection) {
  if (paths.empty()) return false;
  const double direct = paths.front().delay_s;
  return std::any_of(paths.begin(), paths.end(),
                     [&](const SpecularPath& p) { return pathMatchesReflection(p, direct, reflection); });
}

bool explainedByAudiblePaths(const std::vector<SpecularPath>& paths, const RelativeReflection& reflection) {
  if (paths.empty()) return false;
  const SpecularPath& direct_path = paths.front();
  const double direct = direct_path.delay_s;
  // Only a path that could be read as a strong reflection explains one: a weak one (many
  // high orders, a small panel's reflections off the walls) arriving by chance at the same
  // time does not.
  const auto audible = [&](const SpecularPath& p) { return pathLevelDb(p, direct_path) >= kExplainingPathLevelDb; };
  if (std::any_of(paths.begin(), paths.end(),
                  [&](const SpecularPath& p) { return audible(p) && pathMatchesReflection(p, direct, reflection); })) {
    return true;
  }
  // Paths close together in the RSAO's analysis window read as one reflection from their
  // energy-weighted mean direction (a floor and a ceiling reflection 0.3 ms apart read as
  // one from the horizon), which none of them has alone. Each must lie within the match
  // time of the reflection: merging over the whole 2 ms window let a path 0.65 ms early
  // pull a wall path's direction onto a measured reflection neither explains (seed 11 of
  // the planted tests, a phantom panel's path at a held-out pair).
  SpecularPath merged;
  merged.order = 1;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0.0, weighted_delay = 0.0;
  int count = 0;
  for (const SpecularPath& p : paths) {
    if (p.order == 0 || !audible(p) || std::abs((p.delay_s - direct) - reflection.delay_s) > kMatchTimeS) continue;
    const double energy = std::pow(10.0, 0.1 * pathLevelDb(p, direct_path));
    sum += energy * p.arrival_direction;
    weighted_delay += energy * p.delay_s;
    weight += energy;
    ++count;
  }
  if (count < 2 || !(weight > 0.0) || sum.norm() < 1e-12) return false;
  merged.arrival_direction = sum.normalized();
  merged.delay_s = weighted_delay / weight;
  return pathMatchesReflection(merged, direct, reflection);
}

std::vector<UnexplainedReflection> unexplainedReflections(const std::vector<RelativeReflection>& reflections,
                                                          const std::vector<SpecularPath>& paths,
                                                          const MeasurementPair& pair, const AcousticScene& scene,
                                                          double speed_of_sound_m_s, ExplanationRule rule) {
  std::vector<UnexplainedReflection> out;
  const Eigen::Vector3d S = pair.source_m, R = pair.receiver_m;
  const double direct_length = (S - R).norm();
  for (const RelativeReflection& r : strongReflections(reflections)) {
    if (rule == ExplanationRule::kAnyPath ? explainedBySpecularPath(paths, r) : explainedByAudiblePaths(paths, r)) continue;
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
