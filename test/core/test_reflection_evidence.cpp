// The diagnosis's reflection evidence (reflection_evidence.h, unexplained_reflections.h):
// reflections of a first-order response found with their planted time, level and
// direction; a reflection no path explains placed on the surface that made it; the
// reflection term counting exactly the unexplained ones; coincident paths that the RSAO
// merges still explaining the merged reflection; bad input.
#include <gtest/gtest.h>

#include <cmath>

#include "room_reverb/acoustics/propagation.h"
#include "room_reverb/diagnosis/reflection_evidence.h"
#include "shoebox.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

constexpr double kPi = 3.14159265358979323846;

// Unit impulses in first-order AmbiX (ACN W Y Z X, SN3D) from given directions.
struct Arrival {
  double time_s, amplitude, azimuth_rad, elevation_rad;
};
AudioBuffer planeWaves(const std::vector<Arrival>& arrivals, double duration_s = 0.2) {
  AudioBuffer b;
  b.sample_rate_hz = 48000.0;
  b.channels.assign(4, std::vector<float>(static_cast<std::size_t>(duration_s * 48000.0), 0.0f));
  for (const Arrival& a : arrivals) {
    const std::size_t n = static_cast<std::size_t>(std::lround(a.time_s * 48000.0));
    const double ce = std::cos(a.elevation_rad);
    b.channels[0][n] += static_cast<float>(a.amplitude);
    b.channels[1][n] += static_cast<float>(a.amplitude * std::sin(a.azimuth_rad) * ce);
    b.channels[2][n] += static_cast<float>(a.amplitude * std::sin(a.elevation_rad));
    b.channels[3][n] += static_cast<float>(a.amplitude * std::cos(a.azimuth_rad) * ce);
  }
  return b;
}

TEST(ReflectionEvidence, FindsAPlantedReflectionWithItsTimeLevelAndDirection) {
  const auto found = reflectionEvidence(planeWaves({{0.010, 1.0, 0.0, 0.0}, {0.0150, 0.5, kPi / 2, 0.3}}));
  ASSERT_TRUE(found.has_value());
  ASSERT_EQ(found->size(), 1u);
  const RelativeReflection& r = found->front();
  EXPECT_NEAR(r.delay_s, 0.005, 2e-5);
  EXPECT_NEAR(r.level_db, 20.0 * std::log10(0.5), 0.2);
  EXPECT_NEAR(r.azimuth_deg, 90.0, 3.0);
  EXPECT_NEAR(r.elevation_deg, 0.3 * 180.0 / kPi, 3.0);
  EXPECT_EQ(strongReflections(*found).size(), 1u);
}

TEST(ReflectionEvidence, NoEvidenceWithoutDirectionsOrADirectSound) {
  AudioBuffer omni = planeWaves({{0.010, 1.0, 0.0, 0.0}});
  omni.channels.resize(1);
  EXPECT_FALSE(reflectionEvidence(omni).has_value());
  AudioBuffer silent = planeWaves({});
  EXPECT_FALSE(reflectionEvidence(silent).has_value());
}

// A 6 x 5 x 3 m room whose model lacks an upright panel: the measured reflection of the
// panel, made from the panel's geometry, is placed back on it, and the term counts it
// until a path explains it.
struct PanelCase {
  AcousticScene scene{shoeboxMesh({6.0, 5.0, 3.0}), uniformLibrary(0.2, 0.0)};
  MeasurementPair pair;
  std::vector<SpecularPath> paths;
  Eigen::Vector3d panel_point{4.2, 3.4, 1.5};  // on a panel facing -x
  double c = 0.0;
  PanelCase() {
    pair.source_m = {1.5, 1.5, 1.5};
    pair.receiver_m = {2.0, 3.8, 1.5};
    AirConditions air;
    air.enabled = false;
    const PropagationModel model = PropagationModel::from(air, {});
    c = model.speed_of_sound_m_s;
    paths = computeImageSources(scene, pair.source_m, pair.receiver_m, model);
  }
  RelativeReflection panelReflection(double level_db) const {
    const Eigen::Vector3d S = pair.source_m, R = pair.receiver_m;
    const double extra = (S - panel_point).norm() + (panel_point - R).norm() - (S - R).norm();
    const Eigen::Vector3d u = (panel_point - R).normalized();
    RelativeReflection r;
    r.index = 1;
    r.delay_s = extra / c;
    r.level_db = level_db;
    r.azimuth_deg = std::atan2(u.y(), u.x()) * 180.0 / kPi;
    r.elevation_deg = std::asin(u.z()) * 180.0 / kPi;
    return r;
  }
};

TEST(ReflectionEvidence, AnUnexplainedReflectionIsPlacedOnTheSurfaceThatMadeIt) {
  const PanelCase k;
  const RelativeReflection r = k.panelReflection(-6.0);
  ASSERT_FALSE(explainedBySpecularPath(k.paths, r));
  const auto placed = unexplainedReflections({r}, k.paths, k.pair, k.scene, k.c);
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_LT((placed.front().point - k.panel_point).norm(), 0.01);
  // The normal bisects the directions to the source and the receiver.
  const Eigen::Vector3d to_s = (k.pair.source_m - k.panel_point).normalized();
  const Eigen::Vector3d to_r = (k.pair.receiver_m - k.panel_point).normalized();
  EXPECT_GT(placed.front().normal.dot((to_s + to_r).normalized()), 0.9999);
}

TEST(ReflectionEvidence, TheTermCountsEachUnexplainedReflectionByItsLevelAboveTheThreshold) {
  const PanelCase k;
  EXPECT_NEAR(reflectionMismatchJnd({k.panelReflection(-6.0)}, k.paths, k.pair, k.scene, k.c), 8.0, 1e-9);
  // Weak ones, late ones and those whose point would lie outside the room do not count.
  EXPECT_EQ(reflectionMismatchJnd({k.panelReflection(-15.0)}, k.paths, k.pair, k.scene, k.c), 0.0);
  RelativeReflection late = k.panelReflection(-6.0);
  late.delay_s = 0.031;
  EXPECT_EQ(reflectionMismatchJnd({late}, k.paths, k.pair, k.scene, k.c), 0.0);
  // Capped at 10 per reflection, summed over reflections.
  RelativeReflection loud = k.panelReflection(0.0);
  EXPECT_NEAR(reflectionMismatchJnd({loud}, k.paths, k.pair, k.scene, k.c), 10.0, 1e-9);
  // A first-order wall reflection of the model explains its measured counterpart.
  const SpecularPath& wall = k.paths[1];
  RelativeReflection seen;
  seen.index = 1;
  seen.delay_s = wall.delay_s - k.paths.front().delay_s + 0.0002;
  seen.level_db = -5.0;
  seen.azimuth_deg = std::atan2(wall.arrival_direction.y(), wall.arrival_direction.x()) * 180.0 / kPi + 10.0;
  seen.elevation_deg = std::asin(wall.arrival_direction.z()) * 180.0 / kPi;
  EXPECT_TRUE(explainedBySpecularPath(k.paths, seen));
  RelativeReflection astray = seen;  // the same time from the opposite side is not that path
  astray.azimuth_deg += 180.0;
  astray.elevation_deg = -astray.elevation_deg;
  EXPECT_FALSE(explainedBySpecularPath(k.paths, astray));
  EXPECT_EQ(reflectionMismatchJnd({seen, k.panelReflection(-6.0)}, k.paths, k.pair, k.scene, k.c), 8.0);
  // With the panel's path in the model, nothing is left.
  std::vector<SpecularPath> with_panel = k.paths;
  SpecularPath panel_path = wall;
  panel_path.delay_s = k.paths.front().delay_s + k.panelReflection(-6.0).delay_s;
  panel_path.arrival_direction = (k.panel_point - k.pair.receiver_m).normalized();
  with_panel.push_back(panel_path);
  EXPECT_EQ(reflectionMismatchJnd({k.panelReflection(-6.0)}, with_panel, k.pair, k.scene, k.c), 0.0);
}

TEST(ReflectionEvidence, CoincidentPathsExplainTheOneReflectionTheRsaoReadsFromThem) {
  // A floor and a ceiling reflection 0.3 ms apart, at -45 and +45 degrees: the RSAO's 2 ms
  // window reads one arrival from the horizon, 45 degrees from either path.
  SpecularPath direct, floor, ceiling;
  direct.delay_s = 0.005;
  direct.pressure_gain.fill(1.0);
  floor.order = ceiling.order = 1;
  floor.delay_s = 0.0080;
  ceiling.delay_s = 0.0083;
  floor.pressure_gain.fill(0.4);
  ceiling.pressure_gain.fill(0.4);
  floor.arrival_direction = Eigen::Vector3d(1, 0, -1).normalized();
  ceiling.arrival_direction = Eigen::Vector3d(1, 0, 1).normalized();
  RelativeReflection merged;
  merged.delay_s = 0.00315;
  merged.level_db = -5.0;
  EXPECT_TRUE(explainedByAudiblePaths({direct, floor, ceiling}, merged));
  EXPECT_FALSE(explainedByAudiblePaths({direct, floor}, merged));  // one path alone does not
  EXPECT_FALSE(explainedBySpecularPath({direct, floor, ceiling}, merged));  // the placement's rule: path by path
  // Paths 24 dB or more below the direct sound explain nothing under the term's rule.
  SpecularPath faint_floor = floor, faint_ceiling = ceiling;
  faint_floor.pressure_gain.fill(0.05);
  faint_ceiling.pressure_gain.fill(0.05);
  EXPECT_FALSE(explainedByAudiblePaths({direct, faint_floor, faint_ceiling}, merged));
  EXPECT_NEAR(pathLevelDb(floor, direct), 20.0 * std::log10(0.4), 1e-9);
}

}  // namespace
}  // namespace room_reverb::test
