// The diagnosis must find a defect planted in a random room: the planted cause first, its
// parameter near the planted value, no other cause named, the held-out error at least
// halved (of what the planted effect explains: below); and no cause at all when nothing is
// planted. Each test prints its seed
// (ROOM_REVERB_TEST_SEED reruns one).
//
// Each planted case tries its own cause against one rival (rivalsOf below); the case with nothing planted tries the whole catalogue.
// With ROOM_REVERB_FULL_CATALOGUE=1 every case tries the whole catalogue
// (scripts/diagnosis-planted; figures in docs/diagnosis.md): that run takes 846
// simulations, about 17 minutes on 2 cores.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>

#include "planted_room.h"
#include "room_reverb/common/memory_reuse.h"
#include "room_reverb/diagnosis/diagnosis.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

// As the tool and the evaluation node do (memory_reuse.h).
const bool kFreedMemoryKept = (keepFreedMemoryForReuse(), true);

// Of the causes that move the same measures as the planted one, the one whose held-out gain
// comes nearest to the planted cause's, so that the fit must tell the two apart: absorption on a surface
// against air absorption, which both shorten the high bands' decay; scattering against a
// coupled volume, which both bend it; a reflector, a scaled room and a directive source,
// which all change the early energy; room modes against surface absorption in the low
// bands.
std::vector<std::string> rivalsOf(const std::string& planted) {
  const char* full = std::getenv("ROOM_REVERB_FULL_CATALOGUE");
  if (full && std::string(full) == "1") return kCatalogueCauses;
  static const std::map<std::string, std::string> rival = {
      {"air_absorption", "surface_absorption"},
      {"surface_absorption", "air_absorption"},
      {"scattering", "coupled_volume"},
      {"missing_reflector", "geometry_scale"},
      {"geometry_scale", "missing_reflector"},
      {"coupled_volume", "scattering"},
      {"source_directivity", "missing_reflector"},
      {"low_frequency_modes", "surface_absorption"},
      {"diffraction_scattering", "scattering"},
  };
  const std::vector<std::string> causes = {planted, rival.at(planted)};
  std::cout << "[ causes   ] " << causes[0] << " " << causes[1] << " (ROOM_REVERB_FULL_CATALOGUE=1 tries all "
            << kCatalogueCauses.size() << ")\n";
  return causes;
}

struct Outcome {
  Diagnosis d;
  // The held-out error of the truth: the given model with the planted effect, simulated
  // as the diagnosis simulates (same rays and seeds). No diagnosis can do better; what is
  // left there is the ray tracing's own scatter between the "measurement" (30 000 rays)
  // and the model (6000), about 0.7 JND here, mostly in the 2.5 ms early-energy windows.
  double truth_heldout_jnd = 0.0;
};

Outcome run(const PlantedCase& c, const std::vector<std::string>& causes = kCatalogueCauses) {
  const RoomUnderTest room = RoomUnderTest::fromRoomModel(c.room, c.library);
  DiagnosisOptions options = testDiagnosisOptions();
  options.causes = causes;
  Outcome o;
  o.d = diagnose(room, c.evidence, options);
  const Diagnosis& d = o.d;
  const Evaluation truth = ModelEvaluator(room, c.evidence, options.evaluation).evaluate(c.planted);
  o.truth_heldout_jnd = truth.heldout_error_jnd;
  std::cout << "[ result   ] baseline " << d.baseline_error_jnd << " JND, noise " << d.noise_jnd << ", threshold "
            << d.threshold_jnd << ", " << d.simulations << " simulations, " << d.wall_time_s << " s; held out "
            << d.baseline_heldout_jnd << ", truth " << o.truth_heldout_jnd << "\n";
  for (const auto* e : {&d.before, &d.after, &truth}) {
    std::cout << (e == &d.before ? "[ before   ]" : e == &d.after ? "[ after    ]" : "[ truth    ]") << " held out per group:";
    for (const auto& [group, error] : groupMeanAbsoluteErrors(e->terms, 1)) std::cout << " " << group << " " << error;
    std::cout << "\n";
  }
  for (const HypothesisTrial& t : d.trials) {
    std::cout << "[ trial    ] " << t.cause << " gain " << t.heldout_gain_jnd;
    if (t.over_seeds.gains.size() > 1) {
      std::cout << " (over " << t.over_seeds.gains.size() << " seeds " << t.over_seeds.mean_jnd << " +- "
                << t.over_seeds.standard_error_jnd << ")";
    }
    std::cout << ": " << t.note << "\n";
  }
  for (const NamedCause& n : d.causes) {
    std::cout << "[ named    ] " << n.cause << " " << n.target << " held out " << n.heldout_before_jnd << " -> "
              << n.heldout_after_jnd << "\n";
  }
  return o;
}

// The planted cause first and alone, and the held-out error at least halved,
// counted above the truth's: of the error the planted effect explains, at least half
// removed. (Counted from zero, the floor of the truth would set the bar for effects
// confined to a band or two; the raw drop is printed.)
const NamedCause& expectFound(const Outcome& o, const std::string& cause) {
  static const NamedCause none;
  const Diagnosis& d = o.d;
  EXPECT_FALSE(d.causes.empty()) << "no cause named";
  if (d.causes.empty()) return none;
  EXPECT_EQ(d.causes.front().cause, cause);
  EXPECT_EQ(d.causes.size(), 1u) << "another cause was named too: " << d.causes.back().cause;
  const NamedCause& n = d.causes.front();
  const double explained = n.heldout_before_jnd - o.truth_heldout_jnd;
  std::cout << "[ measured ] held out " << n.heldout_before_jnd << " -> " << n.heldout_after_jnd << " ("
            << 100.0 * (1.0 - n.heldout_after_jnd / n.heldout_before_jnd) << " % less); truth " << o.truth_heldout_jnd
            << ": " << 100.0 * (n.heldout_before_jnd - n.heldout_after_jnd) / explained << " % of the explained error removed\n";
  EXPECT_GT(explained, 0.0);
  EXPECT_LE(n.heldout_after_jnd - o.truth_heldout_jnd, 0.5 * explained);
  return n;
}

TEST(DiagnosisPlanted, AirAbsorptionHumidityWithin15Percent) {
  const PlantedCase c = plantedCase("air_absorption", testSeed(11));
  const Outcome o = run(c, rivalsOf(c.cause));
  const NamedCause& n = expectFound(o, "air_absorption");
  if (n.cause != "air_absorption") return;
  const double planted = c.planted.air->humidity_percent;
  EXPECT_NEAR(n.parameters.values.at("humidity_percent"), planted, 0.15 * planted);
}

// Mean over 250 Hz - 4 kHz of the absorption area (m^2) the named cause adds to the room.
double addedAbsorptionAreaM2(const NamedCause& n, const RoomUnderTest& room) {
  double total = 0.0;
  for (std::size_t b = 2; b <= 6; ++b) {
    if (n.target == "all_surfaces") {
      double area = 0.0;
      for (const std::string& t : room.absorptionTargets()) area += room.areaOf(t);
      total += n.parameters.bands.at("absorption_added")[b] * area / 5.0;
    } else {
      total += (n.parameters.bands.at("absorption")[b] - n.parameters.bands.at("absorption_before")[b]) *
               room.areaOf(n.target) / 5.0;
    }
  }
  return total;
}

// The decay times, clarity, DRR and early energy (all omni) fix how much absorption the
// room lacks, not which surface lacks it: with them alone the fit puts it on the planted
// surface in 2 of 7 rooms. The directions of the early energy of the B-format pairs say
// where (early_direction.h); with them the fit finds the planted surface in 9 of 9 rooms
// (seeds 1-8 and 12; ROOM_REVERB_TEST_SEED=s runs one). The test requires the planted surface, its
// absorption within 0.05 (mean 250 Hz-4 kHz), and the absorption area added within two
// decay-time JNDs (10 %) of the room's total absorption area, as Sabine's T ~ V / A
// converts them.
TEST(DiagnosisPlanted, SurfaceAbsorptionOnThePlantedSurfaceWithin005) {
  const PlantedCase c = plantedCase("surface_absorption", testSeed(12));
  const Outcome o = run(c, rivalsOf(c.cause));
  const NamedCause& n = expectFound(o, "surface_absorption");
  if (n.cause != "surface_absorption") return;
  const auto& [target, planted] = *c.planted.absorption.begin();
  const RoomUnderTest room = RoomUnderTest::fromRoomModel(c.room, c.library);
  double planted_area = 0.0, room_area = 0.0;
  for (std::size_t b = 2; b <= 6; ++b) {
    planted_area += (planted[b] - room.absorptionOf(target)[b]) * room.areaOf(target) / 5.0;
    for (const std::string& t : room.absorptionTargets()) {
      room_area += (t == target ? planted[b] : room.absorptionOf(t)[b]) * room.areaOf(t) / 5.0;
    }
  }
  const double fitted_area = addedAbsorptionAreaM2(n, room);
  std::cout << "[ area     ] added " << fitted_area << " m2 (planted " << planted_area << ", room " << room_area
            << "); target " << n.target << (n.target == target ? " (the planted one)" : " (planted: " + target + ")")
            << "\n";
  EXPECT_NEAR(fitted_area, planted_area, 0.10 * room_area);
  ASSERT_EQ(n.target, target);
  const std::vector<double>& fitted = n.parameters.bands.at("absorption");
  double mean_error = 0.0;
  for (std::size_t b = 2; b <= 6; ++b) mean_error += std::abs(fitted[b] - planted[b]) / 5.0;  // 250 Hz - 4 kHz
  EXPECT_LE(mean_error, 0.05);
}

// The room's floor and ceiling absorb and its walls are hard (planted_room.cpp): where
// absorption is spread evenly, scattering changes too little to find.
TEST(DiagnosisPlanted, ScatteringWithin015) {
  const PlantedCase c = plantedCase("scattering", testSeed(13));
  const Outcome o = run(c, rivalsOf(c.cause));
  const NamedCause& n = expectFound(o, "scattering");
  if (n.cause != "scattering") return;
  EXPECT_NEAR(n.parameters.values.at("scattering"), *c.planted.global_scattering, 0.15);
}

// One fit pair hears the panel and places it; a held-out pair hears it at another point
// of it, so the panel must be placed and sized, not only found (panel_extent.h).
TEST(DiagnosisPlanted, MissingReflectorPlacedWithin03m) {
  const PlantedCase c = plantedCase("missing_reflector", testSeed(14));
  const Outcome o = run(c, rivalsOf(c.cause));
  const NamedCause& n = expectFound(o, "missing_reflector");
  if (n.cause != "missing_reflector") return;
  // Distance from the fitted reflection point to the planted panel's surface.
  const CuboidObject& panel = c.planted.reflectors.front();
  const Eigen::Vector3d p(n.parameters.values.at("x_m"), n.parameters.values.at("y_m"), n.parameters.values.at("z_m"));
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(panel.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d local = yaw.transpose() * (p - panel.center_m);
  const Eigen::Vector3d outside = (local.cwiseAbs() - 0.5 * panel.size_m).cwiseMax(0.0);
  EXPECT_LE(outside.norm(), 0.3) << "fitted point " << p.transpose();
}

TEST(DiagnosisPlanted, GeometryScaleWithin002) {
  const PlantedCase c = plantedCase("geometry_scale", testSeed(15));
  const Outcome o = run(c, rivalsOf(c.cause));
  const NamedCause& n = expectFound(o, "geometry_scale");
  if (n.cause != "geometry_scale") return;
  EXPECT_NEAR(n.parameters.values.at("scale"), c.planted.geometry_scale, 0.02);
}

TEST(DiagnosisPlanted, CoupledVolumeDecayTimeWithin30Percent) {
  const PlantedCase c = plantedCase("coupled_volume", testSeed(16));
  const Outcome o = run(c, rivalsOf(c.cause));
  const NamedCause& n = expectFound(o, "coupled_volume");
  if (n.cause != "coupled_volume") return;
  EXPECT_NEAR(n.parameters.values.at("coupled_t60_s"), c.planted.coupled->t60_s, 0.3 * c.planted.coupled->t60_s);
}

TEST(DiagnosisPlanted, SourceDirectivityPatternWithin015AndAxisWithin30Degrees) {
  const PlantedCase c = plantedCase("source_directivity", testSeed(17));
  const Outcome o = run(c, rivalsOf(c.cause));
  const NamedCause& n = expectFound(o, "source_directivity");
  if (n.cause != "source_directivity") return;
  EXPECT_NEAR(n.parameters.values.at("omni_fraction"), c.planted.directivity->omni_fraction, 0.15);
  const double az = n.parameters.values.at("axis_azimuth_deg") * M_PI / 180.0;
  const double el = n.parameters.values.at("axis_elevation_deg") * M_PI / 180.0;
  const Eigen::Vector3d axis(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  EXPECT_GT(axis.dot(c.planted.directivity->axis), std::cos(30.0 * M_PI / 180.0));
}

TEST(DiagnosisPlanted, LowFrequencyModesDampingWithin20Percent) {
  const PlantedCase c = plantedCase("low_frequency_modes", testSeed(19));
  const Outcome o = run(c, rivalsOf(c.cause));
  const NamedCause& n = expectFound(o, "low_frequency_modes");
  if (n.cause != "low_frequency_modes") return;
  EXPECT_NEAR(n.parameters.values.at("damping_scale"), c.planted.modes->damping_scale, 0.2 * c.planted.modes->damping_scale);
}

// Parameter-free physics against the one-coefficient scattering fit that stands in for
// it, in a small room with smooth walls: the diagnosis names the physics. Seeds 1, 2, 5
// and 6 name it; 3 and 4 name nothing (their noise, 0.52 and 0.54 JND, is above the
// gain); none names the scattering.
TEST(DiagnosisPlanted, DiffractionScatteringIsNamedBeforeAFittedScattering) {
  const PlantedCase c = plantedCase("diffraction_scattering", testSeed(1));
  const Outcome o = run(c, rivalsOf(c.cause));
  expectFound(o, "diffraction_scattering");
}

TEST(DiagnosisPlanted, NothingPlantedNamesNoCause) {
  const PlantedCase c = plantedCase("", testSeed(18));
  const Outcome o = run(c);
  EXPECT_TRUE(o.d.causes.empty()) << "named " << (o.d.causes.empty() ? "" : o.d.causes.front().cause);
}

}  // namespace
}  // namespace room_reverb::test
