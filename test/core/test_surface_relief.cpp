// The scattering of a surface's relief: Kirchhoff's phase screen against the integral
// worked numerically, its limits, the room model's relief_scattering key and scene, and
// the visual route's estimate of a wall's relief from a scanned room whose clutter is
// known.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/relief_scattering.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/common/error.h"
#include "room_reverb/metrics/impulse_response_metrics.h"
#include "room_reverb/synthetic_capture/cluttered_rooms.h"
#include "room_reverb/vision/room_layout.h"
#include "room_reverb/vision/surface_relief.h"
#include "room_scan.h"
#include "shipped_materials.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kC = 343.0;
constexpr double kPi = 3.14159265358979323846;

// 1 - int_0^1 2 mu |mean_j exp(i 2 k z_j mu)|^2 dmu by the midpoint rule on 20 000 steps:
// the definition, summed directly rather than through the closed form of g.
double scatteringByQuadrature(const std::vector<double>& heights, double frequency_hz) {
  const double k = 2.0 * kPi * frequency_hz / kC;
  const int steps = 20000;
  double specular = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double mu = (i + 0.5) / steps;
    std::complex<double> mean = 0.0;
    for (double z : heights) mean += std::polar(1.0, 2.0 * k * z * mu);
    mean /= static_cast<double>(heights.size());
    specular += std::norm(mean) * 2.0 * mu / steps;
  }
  return 1.0 - specular;
}

std::vector<double> twoLevels(double share_raised, double height_m, int cells = 100) {
  std::vector<double> heights(static_cast<std::size_t>(cells), 0.0);
  for (int i = 0; i < std::lround(share_raised * cells); ++i) heights[static_cast<std::size_t>(i)] = height_m;
  return heights;
}

RoomModel plainRoom() {
  RoomModel model;
  model.size_m = {5.0, 4.0, 2.5};
  for (const char* name : kRoomSurfaceNames) model.surfaces[name] = SurfaceAssignment{"plaster_smooth"};
  model.surfaces["ceiling"] = SurfaceAssignment{"acoustic_ceiling_tiles"};
  model.rig_position_m = {2.2, 1.8, 1.5};
  return model;
}

}  // namespace

TEST(ReliefScattering, MatchesTheKirchhoffIntegral) {
  // A wall with 30 % of its area 0.2 m proud, and one whose heights spread over 0.4 m.
  std::vector<double> spread;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> depth(-0.1, 0.3);
  for (int i = 0; i < 60; ++i) spread.push_back(i < 25 ? 0.0 : depth(rng));
  for (const auto& heights : {twoLevels(0.3, 0.2), spread}) {
    const OctaveBandValues s = reliefScattering(heights, kC);
    for (int b = 0; b < kOctaveBandCount - 2; ++b) {  // 63 Hz-4 kHz
      EXPECT_NEAR(s[b], scatteringByQuadrature(heights, octaveCentresHz()[b]), 3e-3) << "band " << b;
    }
  }
}

TEST(ReliefScattering, LimitsOfAPlaneASmallRoughnessAndAHighFrequency) {
  // A plane, and a plane moved off the face, scatter nothing.
  for (double z : {0.0, 0.35}) {
    for (double s : reliefScattering(std::vector<double>(50, z), kC)) EXPECT_NEAR(s, 0.0, 1e-12);
  }
  // Heights of sigma 4 mm: s -> 2 k^2 sigma^2 at 125 Hz (2.7e-4).
  std::vector<double> rough;
  std::mt19937 rng(7);
  std::normal_distribution<double> height(0.0, 0.004);
  for (int i = 0; i < 4000; ++i) rough.push_back(height(rng));
  double mean = 0.0, var = 0.0;
  for (double z : rough) mean += z / rough.size();
  for (double z : rough) var += (z - mean) * (z - mean) / rough.size();
  const double k = 2.0 * kPi * 125.0 / kC;
  EXPECT_NEAR(reliefScattering(rough, kC, OctaveBandValues{125, 125, 125, 125, 125, 125, 125, 125, 125})[0],
              2.0 * k * k * var, 0.15 * 2.0 * k * k * var);
  // Half the face plain, the rest spread over 0.5 m: at 16 kHz only the plain half's
  // coherent share is left, s -> 1 - 0.5^2.
  std::vector<double> half(200, 0.0);
  for (int i = 0; i < 100; ++i) half[static_cast<std::size_t>(i)] = 0.05 + 0.45 * i / 99.0;
  EXPECT_NEAR(reliefScattering(half, kC)[8], 0.75, 0.01);
  // It grows with frequency for a relief deeper than the low bands' wavelengths allow.
  const OctaveBandValues s = reliefScattering(twoLevels(0.4, 0.15), kC);
  EXPECT_LT(s[1], 0.1);
  EXPECT_GT(s[5], 0.4);
}

TEST(ReliefScattering, RefusesWhatIsNotARelief) {
  expectInputError([] { reliefScattering({}, kC); }, {"no heights"});
  expectInputError([] { reliefScattering({0.0, std::nan("")}, kC); }, {"not finite"});
  expectInputError([] { reliefScattering({0.0}, 0.0); }, {"speed of sound"});
}

TEST(ReliefScattering, TheRoomModelCarriesItToTheSceneAfterTheOverrides) {
  RoomModel model = plainRoom();
  OctaveBandValues relief{};
  relief.fill(0.3);
  model.surfaces["wall_x_max"].relief_scattering = relief;
  const RoomModel read = parseRoomModel(roomModelToYaml(model));
  EXPECT_EQ(read.surfaces.at("wall_x_max").relief_scattering, relief);
  EXPECT_EQ(read.surfaces.at("wall_x_min").relief_scattering, OctaveBandValues{});

  const MaterialLibrary& library = room_reverb::test::library();
  const AcousticMaterial& plaster = library.get("plaster_smooth");
  MaterialOverrides overrides;
  overrides.absorption["plaster_smooth"].fill(0.2);
  const AcousticScene scene = roomModelToScene(model, library, overrides);
  // wall_x_max is the fourth used face: triangles 6 and 7.
  for (std::size_t t : {6u, 7u}) {
    const AcousticMaterial& m = scene.material(t);
    EXPECT_EQ(m.name, "plaster_smooth, wall_x_max's relief");
    for (int b = 0; b < kOctaveBandCount; ++b) {
      EXPECT_NEAR(m.scattering[b], 1.0 - (1.0 - plaster.scattering[b]) * 0.7, 1e-12);
      EXPECT_EQ(m.absorption[b], 0.2);  // the override reaches the relief's material
    }
    EXPECT_EQ(scene.mesh().normal(t).x(), -1.0);
  }
  EXPECT_EQ(scene.material(4).scattering, plaster.scattering);  // wall_x_min: no relief
  // A global scattering is every surface's, the relief's included.
  overrides.global_scattering = 0.0;
  const AcousticScene flat = roomModelToScene(model, library, overrides);
  for (std::size_t t = 0; t < flat.mesh().triangleCount(); ++t) EXPECT_EQ(flat.material(t).scattering, OctaveBandValues{});
  // The third-octave view keeps the relief.
  EXPECT_GT(scene.thirdOctaveBands(0).material(6).scattering[4], plaster.scattering[4] + 0.25);
}

TEST(ReliefScattering, ARoomModelRefusesAReliefOutOfRange) {
  const std::string base = roomModelToYaml(plainRoom());
  std::string bad = base;
  bad.replace(bad.find("wall_x_max: {material: plaster_smooth"), 36,
              "wall_x_max: {relief_scattering: [0, 0, 0, 0, 1.5, 0, 0, 0, 0], material: plaster_smooth");
  expectInputError([&] { parseRoomModel(bad); }, {"surfaces.wall_x_max.relief_scattering[4]", "outside [0, 1]"});
  bad = base;
  bad.replace(bad.find("wall_x_max: {material: plaster_smooth"), 36,
              "wall_x_max: {relief_scattering: [0, 0.1], material: plaster_smooth");
  expectInputError([&] { parseRoomModel(bad); }, {"surfaces.wall_x_max.relief_scattering"});
  RoomModel model = plainRoom();
  model.surfaces["floor"].relief_scattering[2] = std::nan("");
  expectInputError([&] { roomModelToYaml(model); }, {"surfaces.floor.relief_scattering", "[0, 1]"});
}

namespace {

// Small boxes, 0.12 m on a side and `depth_m` deep, on a grid of pitch 0.24 m over part
// of wall_x_max: each too small to be an object of the fit, together a quarter of the
// covered part of the wall. Returns the area share of the wall they cover.
double addClutter(RoomModel& model, double depth_m) {
  const double pitch = 0.24, side = 0.12;
  int boxes = 0;
  for (double y = 0.6; y + side < 3.4; y += pitch) {
    for (double z = 0.4; z + side < 2.1; z += pitch) {
      CuboidObject box;
      box.label = "clutter";
      box.material = "wood_panel";
      box.center_m = {model.size_m.x() - depth_m / 2.0, y + side / 2.0, z + side / 2.0};
      box.size_m = {depth_m, side, side};
      model.objects.push_back(box);
      ++boxes;
    }
  }
  return boxes * side * side / (model.size_m.y() * model.size_m.z());
}

std::array<ReliefEstimate, 6> reliefOfScan(const RoomModel& truth, RoomLayout* fitted = nullptr) {
  room_reverb::test::RoomScanOptions scan_options = room_reverb::test::stereoLikeScanOptions(5);
  scan_options.rays = 600000;
  const room_reverb::test::RoomScan scan = room_reverb::test::scanRoomModel(truth, scan_options);
  const RoomLayout layout = fitRoomLayout(scan.cloud);
  if (fitted != nullptr) *fitted = layout;
  return estimateSurfaceRelief(scan.cloud, layout, layout.room_from_rig, RoomLayoutOptions{}).faces;
}

}  // namespace

TEST(SurfaceRelief, APlainRoomHasNone) {
  const std::array<ReliefEstimate, 6> relief = reliefOfScan(plainRoom());
  for (std::size_t f = 0; f < 6; ++f) {
    EXPECT_TRUE(relief[f].estimated) << kRoomSurfaceNames[f];
    EXPECT_GT(relief[f].seen_m2, 5.0) << kRoomSurfaceNames[f];
    EXPECT_LT(relief[f].relief_share, 0.02) << kRoomSurfaceNames[f];
    EXPECT_LT(relief[f].scattering[5], 0.02) << kRoomSurfaceNames[f];
  }
}

TEST(SurfaceRelief, AClutteredWallScattersAsItsClutter) {
  RoomModel truth = plainRoom();
  const double covered = addClutter(truth, 0.25);
  RoomLayout layout;
  const std::array<ReliefEstimate, 6> relief = reliefOfScan(truth, &layout);
  EXPECT_NEAR(layout.model.size_m.x(), 5.0, 0.05);  // the wall stays where it is, behind its clutter
  // The truth's relief over the seen part of the wall: the clutter's share at its depth.
  // The clutter hides some of the wall behind it from the rig, so the seen cells hold a
  // little more clutter than the wall does (0.16 against 0.12 here).
  const ReliefEstimate& wall = relief[3];
  ASSERT_TRUE(wall.estimated);
  EXPECT_GT(wall.relief_share, covered - 0.01);
  EXPECT_LT(wall.relief_share, covered + 0.05);
  EXPECT_NEAR(wall.rms_height_m, 0.25 * std::sqrt(covered), 0.015);
  const OctaveBandValues expected = reliefScattering(twoLevels(covered, 0.25, 1000), kC);
  for (int b = 2; b <= 6; ++b) {
    EXPECT_GT(wall.scattering[b], 0.9 * expected[b]) << "band " << b;
    EXPECT_LT(wall.scattering[b], 1.35 * expected[b]) << "band " << b;
  }
  for (std::size_t f : {0u, 1u, 2u, 4u, 5u}) EXPECT_LT(relief[f].scattering[5], 0.03) << kRoomSurfaceNames[f];
}

TEST(SurfaceRelief, AnObjectsBoxAndWhatItHolds) {
  // A 1 x 1 x 0.8 m box fitted round a desk whose top steps down by 0.4 m over its far
  // 40 %, and whose box the fit placed 0.05 m proud of the side facing the rig (a plane
  // moved, not a relief). Points on a 1 cm grid: the top (two levels) and that side.
  RoomLayout layout;
  layout.model = plainRoom();
  layout.model.objects.push_back(CuboidObject{"desk", "wood_panel", {3.5, 2.0, 0.4}, {1.0, 1.0, 0.8}});
  PointCloud cloud;
  const auto add = [&](double x, double y, double z) {
    CloudPoint point;
    const Eigen::Vector3d rig_frame = Eigen::Vector3d(x, y, z) - layout.model.rig_position_m;
    point.p = rig_frame.cast<float>();
    cloud.points.push_back(point);
    layout.point_surface.push_back(-1);
    layout.point_object.push_back(0);
  };
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j < 100; ++j) {
      const double x = 3.0 + (i + 0.5) / 100.0, y = 1.5 + (j + 0.5) / 100.0;
      add(x, y, x < 3.6 ? 0.8 : 0.4);                 // the top, stepped
      if (i < 80) add(3.05, y, (i + 0.5) / 100.0);    // the side towards the rig, 5 cm inside the box
    }
  }
  const Eigen::Isometry3d room_from_rig(Eigen::Translation3d(layout.model.rig_position_m));
  const SurfaceReliefs relief = estimateSurfaceRelief(cloud, layout, room_from_rig, RoomLayoutOptions{});
  ASSERT_EQ(relief.objects.size(), 1u);
  const ReliefEstimate& got = relief.objects[0];
  ASSERT_TRUE(got.estimated);
  EXPECT_NEAR(got.seen_m2, 1.0 + 0.8, 0.05);
  EXPECT_NEAR(got.relief_share, 0.4 / 1.8, 0.01);
  // The top's own scattering, weighted by its share of the seen area; the side is a plane
  // and scatters nothing.
  const OctaveBandValues top = reliefScattering(twoLevels(0.4, 0.4), kC);
  for (int b = 0; b < kOctaveBandCount; ++b) EXPECT_NEAR(got.scattering[b], top[b] / 1.8, 0.01) << "band " << b;
  EXPECT_GT(got.scattering[4], 0.15);

  applySurfaceRelief(layout, relief);
  EXPECT_EQ(layout.model.objects[0].relief_scattering, got.scattering);
  const RoomModel read = parseRoomModel(roomModelToYaml(layout.model));
  for (int b = 0; b < kOctaveBandCount; ++b) EXPECT_NEAR(read.objects[0].relief_scattering[b], got.scattering[b], 1e-6);
  const AcousticScene scene = roomModelToScene(layout.model, room_reverb::test::library());
  EXPECT_EQ(scene.material(12).name, "wood_panel, objects[0] (desk)'s relief");  // after the box's twelve
  expectInputError([&] { estimateSurfaceRelief(PointCloud{}, layout, Eigen::Isometry3d::Identity(), RoomLayoutOptions{}); },
                   {"point labels do not match"});
  SurfaceReliefOptions bad;
  bad.cell_m = 0.0;
  expectInputError([&] { estimateSurfaceRelief(cloud, layout, room_from_rig, RoomLayoutOptions{}, bad); },
                   {"cell_m must be positive"});
}

namespace {

// T30 averaged over 500 Hz-2 kHz, the paper's Table 1 figure.
double midBandT30(const SimulationResult& result) {
  const MetricsReport m = analyseImpulseResponse(result.impulse_response, 0, {});
  double sum = 0.0;
  for (std::size_t b = 3; b <= 5; ++b) sum += m.bands[b].t30_s.value_or(std::nan(""));
  return sum / 3.0;
}

// The fitted model with the truth's face materials, and each object's material that of
// the truth's object nearest it (wood where none is).
RoomModel withTruthMaterials(RoomModel fitted, const RoomModel& truth) {
  for (auto& [name, surface] : fitted.surfaces) surface.material = truth.surfaces.at(name).material;
  for (CuboidObject& object : fitted.objects) {
    object.material = "wood_panel";
    double best = 1e9;
    for (const CuboidObject& t : truth.objects) {
      const double d = (t.center_m - object.center_m).norm();
      if (d < best) best = d, object.material = t.material;
    }
  }
  return fitted;
}

}  // namespace

// What the relief does to the decay of cluttered rooms as a model from the route hears
// them: each room (synthetic_capture/cluttered_rooms.h; development 1-4, held-out 201-204)
// scanned from its rig as stereo would range it, fitted, its faces' and objects' relief
// estimated, the truth's materials given to the fit, and simulated (accurate mode, the rig
// as listener, a source 2 m away) with and without the relief; Eyring's diffuse-field
// decay of the same model for reference. T30, mean of 500 Hz-2 kHz.
//   ROOM_REVERB_RELIEF_DECAY_REPORT=1 .ws/devel/lib/room_reverb/test_surface_relief --gtest_filter='*Report*'
TEST(SurfaceReliefReport, ClutteredRoomsDecay) {
  if (!std::getenv("ROOM_REVERB_RELIEF_DECAY_REPORT")) GTEST_SKIP() << "set ROOM_REVERB_RELIEF_DECAY_REPORT=1 for the report";
  const MaterialLibrary& library = room_reverb::test::library();
  SimulationSettings settings;
  settings.ambisonic_order = 0;
  settings.rays.threads = 2;
  for (const auto& [set, first] : {std::pair{ClutterSet::kDevelopment, 1}, std::pair{ClutterSet::kHeldOut, 201}}) {
    for (int index = first; index < first + 4; ++index) {
      const ClutteredRoom room = clutteredRoom(set, index);
      room_reverb::test::RoomScanOptions scan_options = room_reverb::test::stereoLikeScanOptions(static_cast<std::uint32_t>(index));
      const room_reverb::test::RoomScan scan = room_reverb::test::scanRoomModel(room.scanned, scan_options);
      RoomLayout layout = fitRoomLayout(scan.cloud);
      applySurfaceRelief(layout, estimateSurfaceRelief(scan.cloud, layout, layout.room_from_rig, RoomLayoutOptions{}));
      const RoomModel relief = withTruthMaterials(layout.model, room.truth);
      RoomModel flat = relief;
      for (auto& [name, surface] : flat.surfaces) surface.relief_scattering = {};
      for (CuboidObject& object : flat.objects) object.relief_scattering = {};
      const AcousticScene with = roomModelToScene(relief, library), without = roomModelToScene(flat, library);
      const Eigen::Vector3d rig = relief.rig_position_m;
      std::optional<Eigen::Vector3d> source;
      for (int k = 0; k < 72 && !source; ++k) {
        const double a = 0.3 + k * kPi / 36.0;
        const Eigen::Vector3d p = rig + 2.0 * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
        if (with.isInside(p) && with.distanceToNearestSurface(p) > 0.3) source = p;
      }
      ASSERT_TRUE(source) << room.name;
      std::string walls;
      for (std::size_t f = 0; f < 6; ++f) {
        char text[32];
        std::snprintf(text, sizeof text, " %.2f", layout.face_relief[f].scattering[4]);
        walls += text;
      }
      double objects = 0.0, area = 0.0;
      for (std::size_t k = 0; k < layout.object_relief.size(); ++k) {
        objects += layout.object_relief[k].seen_m2 * layout.object_relief[k].scattering[4];
        area += layout.object_relief[k].seen_m2;
      }
      const double t_flat = midBandT30(simulateRoom(without, *source, rig, settings));
      const double t_relief = midBandT30(simulateRoom(with, *source, rig, settings));
      SimulationSettings eyring = settings;
      eyring.mode = SimulationMode::kEyring;
      const double t_eyring = midBandT30(simulateRoom(with, *source, rig, eyring));
      std::printf("[ measured ] %-16s relief s(1 kHz) faces%s, objects %.2f (%zu); T30 flat %.3f s, relief %.3f s (%+.0f %%), eyring %.3f s\n",
                  room.name.c_str(), walls.c_str(), area > 0.0 ? objects / area : 0.0, layout.model.objects.size(), t_flat,
                  t_relief, 100.0 * (t_relief / t_flat - 1.0), t_eyring);
    }
  }
}
