#include "room_reverb/evaluation/reflection_matching.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/directions.h"

namespace room_reverb::core {
namespace {

constexpr double kDegreesPerRadian = 57.29577951308232;

}  // namespace

std::vector<RelativeReflection> relativeReflections(const Rsao& rsao) {
  std::vector<RelativeReflection> out;
  if (rsao.reflections.empty() || !(rsao.reflections.front().level > 0.0)) return out;
  const EarlyReflection& direct = rsao.reflections.front();
  for (std::size_t k = 1; k < rsao.reflections.size(); ++k) {
    const EarlyReflection& r = rsao.reflections[k];
    RelativeReflection rel;
    rel.index = static_cast<int>(k);
    rel.delay_s = r.time_of_arrival_s - direct.time_of_arrival_s;
    rel.level_db = 20.0 * std::log10(std::max(r.level, 1e-12) / direct.level);
    rel.azimuth_deg = r.azimuth_rad * kDegreesPerRadian;
    rel.elevation_deg = r.elevation_rad * kDegreesPerRadian;
    out.push_back(rel);
  }
  return out;
}

namespace {

double angleBetweenDeg(const RelativeReflection& a, const RelativeReflection& b) {
  const Eigen::Vector3d u = unitVectorFromAngles(a.azimuth_deg / kDegreesPerRadian, a.elevation_deg / kDegreesPerRadian);
  const Eigen::Vector3d v = unitVectorFromAngles(b.azimuth_deg / kDegreesPerRadian, b.elevation_deg / kDegreesPerRadian);
  return std::acos(std::clamp(u.dot(v), -1.0, 1.0)) * kDegreesPerRadian;
}

}  // namespace

ReflectionMatching matchReflections(const Rsao& measured, const Rsao& simulated, const ReflectionMatchOptions& options) {
  const std::vector<RelativeReflection> m = relativeReflections(measured);
  const std::vector<RelativeReflection> s = relativeReflections(simulated);
  struct Candidate {
    double gap_s;
    std::size_t i, j;
  };
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < m.size(); ++i) {
    for (std::size_t j = 0; j < s.size(); ++j) {
      const double gap = std::abs(s[j].delay_s - m[i].delay_s);
      if (gap <= options.time_tolerance_s) candidates.push_back({gap, i, j});
    }
  }
  // Closest in time first; ties by index keep the result independent of sort stability.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.gap_s != b.gap_s ? a.gap_s < b.gap_s : (a.i != b.i ? a.i < b.i : a.j < b.j);
  });
  std::vector<bool> m_used(m.size(), false), s_used(s.size(), false);
  ReflectionMatching out;
  for (const Candidate& c : candidates) {
    if (m_used[c.i] || s_used[c.j]) continue;
    m_used[c.i] = s_used[c.j] = true;
    MatchedReflection match{m[c.i], s[c.j], 1000.0 * (s[c.j].delay_s - m[c.i].delay_s), angleBetweenDeg(m[c.i], s[c.j]),
                            s[c.j].level_db - m[c.i].level_db};
    out.matched.push_back(match);
  }
  std::sort(out.matched.begin(), out.matched.end(),
            [](const MatchedReflection& a, const MatchedReflection& b) { return a.measured.delay_s < b.measured.delay_s; });
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (!m_used[i]) out.measured_only.push_back(m[i]);
  }
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (!s_used[j]) out.simulated_only.push_back(s[j]);
  }
  return out;
}

}  // namespace room_reverb::core
