#include "reflection_score.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace room_reverb::test {
namespace {

constexpr double kWindowS = 0.030;
constexpr double kLevelFloorDb = -14.0;
constexpr double kComparableDb = -6.0;
constexpr double kIsolationS = 0.0003;
constexpr double kMatchS = 0.0005;
constexpr double kSpeedOfSound = 343.0;  // reflection_rooms.cpp's

double db(double ratio) { return 20.0 * std::log10(ratio); }

double p95(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(v.size()))) - 1];
}

Eigen::Vector3d unitFromAngles(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

// Time to the nearest other image source that is at most 6 dB weaker than images[i].
double comparableNeighbourS(const std::vector<ImageArrival>& images, std::size_t i) {
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < images.size(); ++j) {
    if (j == i || images[j].level < images[i].level * std::pow(10.0, kComparableDb / 20.0)) continue;
    nearest = std::min(nearest, std::abs(images[j].time_s - images[i].time_s));
  }
  return nearest;
}

}  // namespace

void ReflectionScore::add(const ReflectionScore& o) {
  resolvable += o.resolvable;
  found += o.found;
  reported += o.reported;
  real += o.real;
  toa_error_ms.insert(toa_error_ms.end(), o.toa_error_ms.begin(), o.toa_error_ms.end());
  direction_error_deg.insert(direction_error_deg.end(), o.direction_error_deg.begin(), o.direction_error_deg.end());
  image_source_error_m.insert(image_source_error_m.end(), o.image_source_error_m.begin(), o.image_source_error_m.end());
  found_confidence.insert(found_confidence.end(), o.found_confidence.begin(), o.found_confidence.end());
  misses.insert(misses.end(), o.misses.begin(), o.misses.end());
}

double ReflectionScore::toaP95Ms() const { return p95(toa_error_ms); }
double ReflectionScore::directionP95Deg() const { return p95(direction_error_deg); }

std::string ReflectionScore::summary() const {
  char line[256];
  std::snprintf(line, sizeof line,
                "found %d of %d (%.0f %%), toa p95 %.3f ms, direction p95 %.1f deg, real %d of %d reported (%.0f %%)",
                found, resolvable, 100.0 * recall(), toaP95Ms(), directionP95Deg(), real, reported, 100.0 * precision());
  return line;
}

ReflectionScore scoreReflections(const ReflectionRoom& room, const std::vector<core::EarlyReflection>& estimate) {
  ReflectionScore score;
  const std::vector<ImageArrival>& images = room.images;
  const ImageArrival& direct = images.front();
  const double floor = direct.level * std::pow(10.0, kLevelFloorDb / 20.0);

  std::vector<std::size_t> resolvable;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const ImageArrival& a = images[i];
    if (a.order < 1 || a.order > 2 || a.time_s - direct.time_s > kWindowS || a.level < floor) continue;
    if (comparableNeighbourS(images, i) < kIsolationS) continue;
    resolvable.push_back(i);
  }
  score.resolvable = static_cast<int>(resolvable.size());

  // One-to-one matching, nearest pairs first.
  struct Pair {
    double error_s;
    std::size_t truth, estimate;
  };
  std::vector<Pair> pairs;
  for (std::size_t t = 0; t < resolvable.size(); ++t)
    for (std::size_t e = 1; e < estimate.size(); ++e) {
      const double error = std::abs(estimate[e].time_of_arrival_s - images[resolvable[t]].time_s);
      if (error <= kMatchS) pairs.push_back({error, t, e});
    }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.error_s < b.error_s; });
  std::vector<bool> truth_used(resolvable.size(), false), estimate_used(estimate.size(), false);
  for (const Pair& p : pairs) {
    if (truth_used[p.truth] || estimate_used[p.estimate]) continue;
    truth_used[p.truth] = estimate_used[p.estimate] = true;
    const ImageArrival& truth = images[resolvable[p.truth]];
    const core::EarlyReflection& r = estimate[p.estimate];
    ++score.found;
    score.toa_error_ms.push_back(1000.0 * p.error_s);
    const double cosine = std::clamp(unitFromAngles(r.azimuth_rad, r.elevation_rad).dot(truth.direction), -1.0, 1.0);
    score.direction_error_deg.push_back(std::acos(cosine) * 180.0 / 3.14159265358979323846);
    const auto image = core::imageSourcePosition(r);
    const Eigen::Vector3d true_image = kSpeedOfSound * truth.time_s * truth.direction;
    score.image_source_error_m.push_back((Eigen::Vector3d(image[0], image[1], image[2]) - true_image).norm());
    score.found_confidence.push_back(r.confidence.value_or(-1.0));
  }
  for (std::size_t t = 0; t < resolvable.size(); ++t) {
    if (truth_used[t]) continue;
    const ImageArrival& a = images[resolvable[t]];
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t e = 1; e < estimate.size(); ++e) {
      const double d = estimate[e].time_of_arrival_s - a.time_s;
      if (std::abs(d) < std::abs(nearest)) nearest = d;
    }
    score.misses.push_back({room.name, 1000.0 * (a.time_s - direct.time_s), db(a.level / direct.level), a.order,
                            1000.0 * comparableNeighbourS(images, resolvable[t]), 1000.0 * nearest});
  }

  for (std::size_t e = 1; e < estimate.size(); ++e) {
    if (estimate[e].time_of_arrival_s - direct.time_s > kWindowS) continue;
    ++score.reported;
    const bool real = std::any_of(images.begin(), images.end(), [&](const ImageArrival& a) {
      return a.order >= 1 && std::abs(a.time_s - estimate[e].time_of_arrival_s) <= kMatchS;
    });
    if (real) ++score.real;
  }
  return score;
}

}  // namespace room_reverb::test
