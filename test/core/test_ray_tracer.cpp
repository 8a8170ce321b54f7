// Ray tracing and the accurate simulation in shoeboxes, against energy conservation,
// diffuse-field theory and Eyring's formula.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/acoustics/triangle_visibility.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/sample_statistics.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"
#include "shoebox.h"
#include "test_rooms.h"

using namespace room_reverb::core;
using room_reverb::test::noAir;
using room_reverb::test::twoThreads;

TEST(RayTracer, LosslessRoomKeepsItsEnergyAndHoldsTheDiffuseFieldLevel) {
  const Eigen::Vector3d size(5, 4, 3);
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.0, 0.5));
  const PropagationModel model = PropagationModel::from(noAir(), {});
  const RayTracingOptions options = twoThreads(4000, 0.4);
  const RayTracingResult result = traceRays(scene, {1.2, 1.1, 1.3}, {3.6, 2.7, 1.7}, model, options);
  EXPECT_EQ(result.stats.leaked_rays, 0u);
  EXPECT_EQ(result.stats.rays, 4000u);
  for (int b = 0; b < kOctaveBandCount; ++b) EXPECT_NEAR(result.stats.energy_left_at_time_limit[b], 1.0, 0.01);
  // A lossless diffuse field of 1 J in V holds energy density 1/V; through a unit area it
  // carries c/V per second. Compare the histogram's mean level over 0.1-0.4 s.
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t bin = 100; bin < result.histogram.bins(); ++bin, ++count) sum += result.histogram.energy(bin, 4);
  const double expected = model.speed_of_sound_m_s / (size.prod()) * options.bin_s;
  EXPECT_NEAR(sum / count / expected, 1.0, 0.05);
}

TEST(RayTracer, TheTrackReceiverHoldsTheDiffuseFieldLevelAndAgreesWithTheSphere) {
  // The lossless diffuse field again: the track each ray runs within 1 m of the listener,
  // over the sphere's volume, is the fluence c/V per second, as the crossings of the
  // detection sphere give. One sphere clear of the walls, one cut by the floor: only the
  // part inside the room counts, so the level holds.
  const Eigen::Vector3d size(5, 4, 3);
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.0, 0.5));
  const PropagationModel model = PropagationModel::from(noAir(), {});
  RayTracingOptions options = twoThreads(4000, 0.4);
  options.track_radius_m = 1.0;
  const double expected = model.speed_of_sound_m_s / size.prod() * options.bin_s;
  for (const Eigen::Vector3d& listener : {Eigen::Vector3d(3.0, 2.2, 1.6), Eigen::Vector3d(3.0, 2.2, 0.4)}) {
    const RayTracingResult result = traceRays(scene, {1.2, 1.1, 1.3}, listener, model, options);
    EXPECT_DOUBLE_EQ(result.stats.receiver_radius_m, 1.0);
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t bin = 100; bin < result.histogram.bins(); ++bin, ++count) sum += result.histogram.energy(bin, 4);
    std::cout << "[ measured ] track receiver at z " << listener.z() << " m: " << sum / count / expected
              << " of the diffuse field's level\n";
    EXPECT_NEAR(sum / count / expected, 1.0, 0.03);
  }
  // With absorption the two receivers read the same decay: the 1 kHz energy over
  // 50-150 ms and 150-300 ms, 20 000 rays each (the material is the same in every band).
  const AcousticScene absorbing(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.2, 0.3));
  RayTracingOptions sphere = twoThreads(20000, 0.3);
  RayTracingOptions track = sphere;
  track.track_radius_m = 1.2;
  const Eigen::Vector3d source(1.2, 1.1, 1.3), listener(3.4, 2.6, 1.5);
  const RayTracingResult by_sphere = traceRays(absorbing, source, listener, model, sphere);
  const RayTracingResult by_track = traceRays(absorbing, source, listener, model, track);
  auto window = [](const EnergyHistogram& h, int band, std::size_t from, std::size_t to) {
    double sum = 0.0;
    for (std::size_t k = from; k < to; ++k) sum += h.energy(k, band);
    return sum;
  };
  for (const auto& [from, to] : {std::pair<std::size_t, std::size_t>{50, 150}, {150, 300}}) {
    const double ratio = window(by_track.histogram, 4, from, to) / window(by_sphere.histogram, 4, from, to);
    std::cout << "[ measured ] " << from << "-" << to << " ms: track / sphere " << ratio << "\n";
    EXPECT_NEAR(ratio, 1.0, 0.08) << from;
  }
  RayTracingOptions bad = options;
  for (double radius : {-1.0, std::nan("")}) {
    bad.track_radius_m = radius;
    EXPECT_THROW(traceRays(scene, {1.2, 1.1, 1.3}, {3, 2, 1.5}, model, bad), InputError);
  }
}

TEST(AcousticScene, TheFreeVolumeOfASphereIsThePartInsideTheRoom) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({5, 4, 3}), room_reverb::test::uniformLibrary(0.1, 0.1));
  const double sphere = 4.0 / 3.0 * M_PI;
  EXPECT_NEAR(scene.freeVolumeInSphereM3({2.5, 2.0, 1.5}, 1.0), sphere, 1e-9);  // clear of every wall
  EXPECT_NEAR(scene.freeVolumeInSphereM3({2.5, 2.0, 0.0}, 1.0) / sphere, 0.5, 0.02);  // centred on the floor
  EXPECT_NEAR(scene.freeVolumeInSphereM3({0.0, 0.0, 0.0}, 1.0) / sphere, 0.125, 0.02);  // in a corner
  EXPECT_NEAR(scene.freeVolumeInSphereM3({2.5, 2.0, 1.5}, 10.0), 60.0, 60.0 * 0.03);  // holds the room
}

TEST(RayTracer, SameSeedSameOutputDifferentSeedSameDecay) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({5, 4, 3}), room_reverb::test::uniformLibrary(0.2, 0.6));
  SimulationSettings settings;
  settings.duration_s = 1.0;
  settings.ambisonic_order = 1;
  settings.air = noAir();
  settings.rays.ray_count = 20000;
  settings.rays.threads = 2;
  settings.rays.seed = 7;
  const Eigen::Vector3d source(1.2, 1.1, 1.3), listener(3.6, 2.7, 1.7);
  const SimulationResult a = simulateRoom(scene, source, listener, settings);
  const SimulationResult b = simulateRoom(scene, source, listener, settings);
  ASSERT_EQ(a.impulse_response.channels, b.impulse_response.channels);
  settings.rays.seed = 8;
  const SimulationResult c = simulateRoom(scene, source, listener, settings);
  EXPECT_NE(a.impulse_response.channels[0], c.impulse_response.channels[0]);
  const MetricsReport ma = computeRoomAcousticParameters(a.impulse_response.channels[0], 48000.0);
  const MetricsReport mc = computeRoomAcousticParameters(c.impulse_response.channels[0], 48000.0);
  for (std::size_t band = 3; band < 8; ++band) {
    ASSERT_TRUE(ma.bands[band].t30_s && mc.bands[band].t30_s) << ma.bands[band].reason;
    // Measured here: within 2.2 % at 20 000 rays (the 2 % is for the default
    // 100 000 rays; this small version allows 3 %).
    EXPECT_NEAR(*ma.bands[band].t30_s / *mc.bands[band].t30_s, 1.0, 0.03) << ma.bands[band].nominal_hz;
  }
}

TEST(RoomSimulation, AccurateShoeboxDecayFollowsEyring) {
  const Eigen::Vector3d size(6, 4, 3);
  for (double alpha : {0.05, 0.2, 0.5}) {
    const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(alpha, 0.7));
    SimulationSettings settings;
    settings.air = noAir();
    const double eyring = eyringReverberationTimes(scene, settings.air)[4];
    settings.duration_s = std::min(3.0, 1.2 * eyring + 0.3);
    settings.ambisonic_order = 0;
    settings.rays.ray_count = 20000;
    settings.rays.threads = 2;
    const SimulationResult result = simulateRoom(scene, {1.5, 1.2, 1.4}, {4.3, 2.9, 1.6}, settings);
    const MetricsReport metrics = computeRoomAcousticParameters(result.impulse_response.channels[0], 48000.0);
    for (std::size_t band = 3; band <= 6; ++band) {  // 500 Hz - 4 kHz
      const auto& p = metrics.bands[band];
      ASSERT_TRUE(p.t20_s) << alpha << " " << p.reason;
      const double t = p.t30_s ? *p.t30_s : *p.t20_s;
      // At alpha = 0.5 the simulated decay is 11-13 % longer than Eyring's, as Kuttruff's
      // path-length-variance correction predicts for a shoebox; open point (see issue notes).
      EXPECT_NEAR(t / eyring, 1.0, alpha < 0.4 ? 0.10 : 0.15) << "alpha " << alpha << ", " << p.nominal_hz << " Hz, Eyring " << eyring;
    }
  }
}

TEST(RoomSimulation, EyringModeTailFollowsEyringWithAir) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({6, 4, 3}), room_reverb::test::uniformLibrary(0.15, 0.3));
  SimulationSettings settings;
  settings.mode = SimulationMode::kEyring;
  settings.duration_s = 2.0;
  settings.ambisonic_order = 0;
  const SimulationResult result = simulateRoom(scene, {1.5, 1.2, 1.4}, {4.3, 2.9, 1.6}, settings);
  const MetricsReport metrics = computeRoomAcousticParameters(result.impulse_response.channels[0], 48000.0);
  for (std::size_t band = 2; band <= 7; ++band) {
    ASSERT_TRUE(metrics.bands[band].t30_s) << metrics.bands[band].reason;
    // Measured: within 8 % (the image-source early part and the fade shape the first 35 dB).
    EXPECT_NEAR(*metrics.bands[band].t30_s / result.eyring_t60_s[band], 1.0, 0.10) << metrics.bands[band].nominal_hz;
  }
}

// The energy in flight is conserved in a closed lossless room (every bin holds the 1 J
// emitted) and falls as exp(-m c t) with air alone.
TEST(RayTracer, EnergyInFlightIsConservedAndFallsWithAir) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({5, 4, 3}), room_reverb::test::uniformLibrary(0.0, 0.5));
  RayTracingOptions options;
  options.ray_count = 500;
  options.max_time_s = 0.5;
  options.record_energy_in_flight = true;
  const Eigen::Vector3d source(1.2, 1.1, 1.3), listener(3.6, 2.7, 1.7);
  const RayTracingResult lossless = traceRays(scene, source, listener, PropagationModel::from(noAir(), {}), options);
  ASSERT_EQ(lossless.energy_in_flight.size(), 500u);
  for (const OctaveBandValues& bin : lossless.energy_in_flight) {
    for (double e : bin) ASSERT_NEAR(e, 1.0, 1e-9);
  }
  // Without the image sources' paths (specular, up to order 3): nothing while every ray is
  // on its first leg, everything once every ray has been reflected more than three times
  // (the longest leg in a 5 x 4 x 3 m box is 7.1 m: 28.4 m, 83 ms), part of it between.
  ASSERT_EQ(lossless.late_energy_in_flight.size(), 500u);
  EXPECT_NEAR(lossless.late_energy_in_flight[0][4], 0.0, 1e-12);
  EXPECT_GT(lossless.late_energy_in_flight[20][4], 0.05);
  EXPECT_LT(lossless.late_energy_in_flight[20][4], 0.95);
  for (std::size_t k = 90; k < 500; k += 41) EXPECT_NEAR(lossless.late_energy_in_flight[k][4], 1.0, 1e-9) << k;
  AirConditions air;  // 20 C, 50 %
  const PropagationModel model = PropagationModel::from(air, {});
  const RayTracingResult with_air = traceRays(scene, source, listener, model, options);
  for (std::size_t k = 0; k < with_air.energy_in_flight.size(); k += 50) {
    const double distance = (k + 0.5) * options.bin_s * model.speed_of_sound_m_s;
    for (int b = 0; b < kOctaveBandCount; ++b) {
      // The air factor is taken at each bin's start: within m c bin_s of the exact value.
      const double expected = std::exp(-model.air_attenuation_per_m[b] * distance);
      EXPECT_NEAR(with_air.energy_in_flight[k][b] / expected, 1.0, model.air_attenuation_per_m[b] * 0.35 + 1e-9) << k << " " << b;
    }
  }
  RayTracingOptions without = options;
  without.record_energy_in_flight = false;
  EXPECT_TRUE(traceRays(scene, source, listener, model, without).energy_in_flight.empty());
}

// A room whose absorption sits on the floor and ceiling (carpet, ceiling tiles) between
// hard walls, with low scattering: Eyring's mean absorption makes the decay far too short,
// since the sound that lasts travels between the hard walls. The fast mode follows the
// room's own decay: its T20, the mean over three seeds, is within 15 % of the accurate
// mode's in every octave 250 Hz - 2 kHz; the eyring mode's is not. Its EDT is too: the
// track receiver hears the diffuse energy of the first reflections, which a diffuse field
// faded in after the image sources leaves out. (This room is used by no other check;
// docs/simulation.md has the figures of the sample room and others.)
TEST(RoomSimulation, FastModeFollowsTheDecayWhereTheAbsorptionIsUneven) {
  const AcousticScene scene = roomModelToScene(room_reverb::test::unevenAbsorptionRoom(), MaterialLibrary::loadDefault(), {});
  const Eigen::Vector3d source(1.8, 1.6, 1.5), listener(5.1, 3.4, 1.3);
  SimulationSettings settings;
  settings.duration_s = 2.0;
  settings.ambisonic_order = 0;
  settings.rays.ray_count = 30000;
  auto t20 = [&](SimulationMode mode, std::uint32_t seed) {
    settings.mode = mode;
    settings.rays.seed = seed;
    const SimulationResult r = simulateRoom(scene, source, listener, settings);
    return computeRoomAcousticParameters(r.impulse_response.channels[0], 48000.0);
  };
  const MetricsReport accurate = t20(SimulationMode::kAccurate, 1);
  const MetricsReport eyring = t20(SimulationMode::kEyring, 1);
  std::vector<MetricsReport> fast;
  for (std::uint32_t seed = 1; seed <= 3; ++seed) fast.push_back(t20(SimulationMode::kFast, seed));
  int eyring_misses = 0;
  for (std::size_t band = 2; band <= 5; ++band) {
    ASSERT_TRUE(accurate.bands[band].t20_s && eyring.bands[band].t20_s);
    double mean = 0.0;
    for (const MetricsReport& m : fast) {
      ASSERT_TRUE(m.bands[band].t20_s) << m.bands[band].reason;
      mean += *m.bands[band].t20_s / 3.0;
    }
    const double reference = *accurate.bands[band].t20_s;
    double edt = 0.0;
    for (const MetricsReport& m : fast) {
      ASSERT_TRUE(m.bands[band].edt_s);
      edt += *m.bands[band].edt_s / 3.0;
    }
    ASSERT_TRUE(accurate.bands[band].edt_s);
    std::cout << "[ measured ] " << accurate.bands[band].nominal_hz << " Hz: T20 accurate " << reference << " s, fast "
              << mean << " s, eyring " << *eyring.bands[band].t20_s << " s; EDT accurate " << *accurate.bands[band].edt_s
              << " s, fast " << edt << " s\n";
    EXPECT_NEAR(mean / reference, 1.0, 0.15) << accurate.bands[band].nominal_hz;
    EXPECT_NEAR(edt / *accurate.bands[band].edt_s, 1.0, 0.15) << accurate.bands[band].nominal_hz;
    if (std::abs(*eyring.bands[band].t20_s / reference - 1.0) > 0.4) ++eyring_misses;
  }
  EXPECT_EQ(eyring_misses, 4);
}

TEST(RoomSimulation, BadPositionsAndSettingsAreClearErrors) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({5, 4, 3}), room_reverb::test::uniformLibrary(0.2, 0.2));
  SimulationSettings settings;
  settings.duration_s = 0.2;
  settings.rays.ray_count = 100;
  const Eigen::Vector3d inside(2, 2, 1.5);
  EXPECT_THROW(simulateRoom(scene, {7, 2, 1.5}, inside, settings), InputError);   // outside
  EXPECT_THROW(simulateRoom(scene, inside, {2, 2, -1}, settings), InputError);    // below the floor
  EXPECT_THROW(simulateRoom(scene, {5.0, 2, 1.5}, inside, settings), InputError); // on a wall
  EXPECT_THROW(simulateRoom(scene, {NAN, 2, 1.5}, inside, settings), InputError);
  settings.rays.ray_count = 0;
  EXPECT_THROW(simulateRoom(scene, {1, 1, 1}, inside, settings), InputError);
  settings.rays.ray_count = 100;
  settings.ambisonic_order = 5;
  EXPECT_THROW(simulateRoom(scene, {1, 1, 1}, inside, settings), InputError);
  EXPECT_THROW(room_reverb::test::uniformLibrary(1.5, 0.2), InputError);
  MaterialOverrides typo;
  typo.absorption["test_wal"].fill(0.3);
  EXPECT_THROW(AcousticScene(room_reverb::test::shoeboxMesh({5, 4, 3}), room_reverb::test::uniformLibrary(0.2, 0.2), typo), InputError);
  MaterialOverrides out_of_range;
  out_of_range.scattering["test_wall"].fill(1.2);
  EXPECT_THROW(AcousticScene(room_reverb::test::shoeboxMesh({5, 4, 3}), room_reverb::test::uniformLibrary(0.2, 0.2), out_of_range), InputError);
  EXPECT_THROW(parseSimulationMode("exact"), InputError);
  for (const char* name : {"fast", "accurate", "eyring"}) EXPECT_EQ(toString(parseSimulationMode(name)), name);
  settings.mode = SimulationMode::kFast;
  settings.fast_ray_count = 0;
  EXPECT_THROW(simulateRoom(scene, {1, 1, 1}, inside, settings), InputError);
}

namespace {

// Energy per band in [from_s, to_s) of a histogram.
double windowEnergy(const EnergyHistogram& histogram, int band, double from_s, double to_s) {
  double sum = 0.0;
  for (std::size_t bin = static_cast<std::size_t>(from_s / histogram.binS()); bin < static_cast<std::size_t>(to_s / histogram.binS()); ++bin) {
    sum += histogram.energy(bin, band);
  }
  return sum;
}

}  // namespace

// Bands that scatter differently share a ray until they disagree, then split; each band's
// path must be exactly what it would be alone. Truth per band: the same room with that
// band's scattering coefficient in every band (nothing to split). A tracer that instead
// chose one path for all bands and reweighted them (s/p, (1-s)/(1-p)) missed this by up
// to 45 % in T20 at 30 000 rays (docs/simulation.md), so the bounds below catch it.
TEST(RayTracer, BandsWithDifferentScatteringEachDecayAsIfAlone) {
  const Eigen::Vector3d size(6, 4, 3), source(1.5, 1.2, 1.4), listener(4.2, 2.9, 1.6);
  const OctaveBandValues scattering{0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 0.95};
  const PropagationModel model = PropagationModel::from(noAir(), {});
  RayTracingOptions options;
  options.ray_count = 10000;
  options.max_time_s = 0.8;
  options.threads = 2;
  AcousticMaterial wall = room_reverb::test::uniformLibrary(0.12, 0.0).get("test_wall");
  wall.scattering = scattering;
  MaterialLibrary graded;
  graded.add(wall);
  const RayTracingResult mixed = traceRays(AcousticScene(room_reverb::test::shoeboxMesh(size), graded), source, listener, model, options);
  const double windows[][2] = {{0.05, 0.2}, {0.2, 0.45}, {0.45, 0.8}};
  for (int b = 0; b < kOctaveBandCount; ++b) {
    const AcousticScene alone(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.12, scattering[b]));
    options.seed = 2;
    const RayTracingResult truth = traceRays(alone, source, listener, model, options);
    options.seed = 1;
    for (const auto& w : windows) {
      const double ratio = windowEnergy(mixed.histogram, b, w[0], w[1]) / windowEnergy(truth.histogram, b, w[0], w[1]);
      EXPECT_NEAR(ratio, 1.0, 0.1) << "band " << b << ", " << w[0] << "-" << w[1] << " s";
    }
  }
}

// The automatic detection sphere is sized so that N pi r^2 c / V rays cross it per
// millisecond (ray_tracer.h); in a lossless, purely specular room the rays fill the volume
// evenly and the count of crossings over 0.2 s must match, and rise fourfold with
// crossings_per_ms (the sphere's radius twofold) at the same ray count. Measured: 0.975 of
// the count over seeds 1-3 at both settings (the first milliseconds, before the rays reach
// the sphere, have none).
TEST(RayTracer, TheAutomaticSphereIsCrossedAsOftenAsItWasSizedFor) {
  const Eigen::Vector3d size(10, 8, 4);
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.0, 0.0));
  const PropagationModel model = PropagationModel::from(noAir(), {});
  RayTracingOptions options = twoThreads(200000, 0.2);
  options.image_source_order = -1;  // count every crossing, the image sources' too
  options.diffuse_rain = false;
  const Eigen::Vector3d source(2.5, 2.0, 1.5), listener(5.0, 4.0, 2.0);
  const RayTracingResult at300 = traceRays(scene, source, listener, model, options);
  options.crossings_per_ms = 1200.0;
  const RayTracingResult at1200 = traceRays(scene, source, listener, model, options);
  EXPECT_NEAR(at1200.stats.receiver_radius_m / at300.stats.receiver_radius_m, 2.0, 1e-9);
  EXPECT_NEAR(static_cast<double>(at300.stats.sphere_detections) / (300.0 * 200.0), 1.0, 0.05);
  EXPECT_NEAR(static_cast<double>(at1200.stats.sphere_detections) / (1200.0 * 200.0), 1.0, 0.05);
  // The shortfall is the same share at both counts (measured 4.007 times as many).
  EXPECT_NEAR(static_cast<double>(at1200.stats.sphere_detections) / static_cast<double>(at300.stats.sphere_detections), 4.0, 0.04);
  options.crossings_per_ms = 0.0;
  EXPECT_THROW(traceRays(scene, source, listener, model, options), InputError);
}

// Common random numbers: the tracer's decisions are keyed by ray, branch and reflection, so
// two rooms that differ in one surface (here the floor: absorption and scattering 0.30 ->
// 0.35) traced with the same seed follow the same paths until a decision on that floor
// flips. The difference between them at one seed is then much less noisy than between
// independent seeds, which is what lets the diagnosis measure a fit's gain seed by seed.
// Measured (12 seeds, 2000 rays, log window energy at 1 kHz): paired / unpaired spread 0.29
// (20-100 ms) and 0.35 (100-400 ms); with one running generator per chunk of 256 rays
// instead, 1.62 and 0.73 (a flip there moves every later ray of the chunk onto new
// numbers).
TEST(RayTracer, OneSurfaceChangedAtTheSameSeedChangesLittleElse) {
  const Eigen::Vector3d size(6, 4, 3), source(1.5, 1.2, 1.4), listener(4.2, 2.9, 1.6);
  TriangleMesh mesh = room_reverb::test::shoeboxMesh(size);
  mesh.triangle_material[0] = mesh.triangle_material[1] = mesh.materialIndex("floor");  // the z = 0 face
  auto withFloor = [&](double coefficient) {
    MaterialLibrary library = room_reverb::test::uniformLibrary(0.1, 0.2);
    library.add(room_reverb::test::uniformLibrary(coefficient, coefficient, "floor").get("floor"));
    return AcousticScene(mesh, library);
  };
  const AcousticScene before = withFloor(0.30), after = withFloor(0.35);
  const PropagationModel model = PropagationModel::from(noAir(), {});
  RayTracingOptions options = twoThreads(2000, 0.5);
  const double windows[][2] = {{0.02, 0.1}, {0.1, 0.4}};
  for (const auto& w : windows) {
    std::vector<double> paired, unpaired;
    for (std::uint32_t seed = 1; seed <= 12; ++seed) {
      options.seed = seed;
      const double a = std::log(windowEnergy(traceRays(before, source, listener, model, options).histogram, 4, w[0], w[1]));
      const double b = std::log(windowEnergy(traceRays(after, source, listener, model, options).histogram, 4, w[0], w[1]));
      options.seed = seed + 100;
      const double c = std::log(windowEnergy(traceRays(after, source, listener, model, options).histogram, 4, w[0], w[1]));
      paired.push_back(b - a);
      unpaired.push_back(c - a);
    }
    EXPECT_LT(sampleStandardDeviation(paired), 0.5 * sampleStandardDeviation(unpaired)) << w[0] << "-" << w[1] << " s";
  }
}

TEST(TriangleVisibility, TheListenerSeesEveryWallOfAnEmptyBoxWholeAndNotWhatAnObjectHides) {
  // An empty shoebox: nothing can hide any of its twelve triangles (neighbours only touch).
  const TriangleMesh box = room_reverb::test::shoeboxMesh({5, 4, 3});
  const TriangleVisibility empty(box, {2.0, 1.5, 1.2});
  ASSERT_EQ(empty.triangleCount(), box.triangleCount());
  for (std::size_t t = 0; t < empty.triangleCount(); ++t) EXPECT_TRUE(empty.seenWhole(t)) << t;
  // A pillar between the listener and the x = 5 wall: that wall is not seen whole, the
  // x = 0 wall behind the listener still is.
  RoomModel model = room_reverb::test::plasterRoom({5.0, 4.0, 3.0});
  model.objects.push_back(room_reverb::test::woodCuboid("pillar", {3.8, 2.0, 1.5}, {0.4, 0.4, 3.0}));
  const AcousticScene scene = roomModelToScene(model, MaterialLibrary::loadDefault(), {});
  const Eigen::Vector3d listener(2.0, 2.0, 1.5);
  const TriangleVisibility seen(scene.mesh(), listener);
  std::size_t hidden_far = 0, seen_near = 0, far = 0, near = 0;
  for (std::size_t t = 0; t < seen.triangleCount(); ++t) {
    const TriangleMesh& mesh = scene.mesh();
    const Eigen::Vector3d centre =
        (mesh.vertices[mesh.triangles[t][0]] + mesh.vertices[mesh.triangles[t][1]] + mesh.vertices[mesh.triangles[t][2]]) / 3.0;
    if (std::abs(centre.x() - 5.0) < 1e-9) {
      ++far;
      if (!seen.seenWhole(t)) ++hidden_far;
    }
    if (std::abs(centre.x()) < 1e-9) {
      ++near;
      if (seen.seenWhole(t)) ++seen_near;
    }
  }
  EXPECT_GT(far, 0u);
  EXPECT_EQ(hidden_far, far);
  EXPECT_GT(near, 0u);
  EXPECT_EQ(seen_near, near);
  // More triangles than the limit: each ray decides.
  const TriangleVisibility limited(box, {2.0, 1.5, 1.2}, 3, 4);
  for (std::size_t t = 0; t < box.triangleCount(); ++t) {
    EXPECT_FALSE(limited.seenWhole(t));
    EXPECT_FALSE(limited.sees(t, box.vertices[box.triangles[t][0]]));
  }
}

TEST(TriangleVisibility, ACellItCallsSeenIsSeenAndMostOfWhatIsSeenNeedsNoRay) {
  // Three objects in a room hide parts of its walls and floor from the listener. Points
  // on every triangle that is not seen whole: where the cells say "seen", the scene's own
  // ray must find the way clear, and the cells must settle most of the points that are
  // seen (the rain's rays they save).
  RoomModel model = room_reverb::test::plasterRoom({6.0, 5.0, 3.0});
  model.objects.push_back(room_reverb::test::woodCuboid("pillar", {4.5, 2.5, 1.5}, {0.4, 0.4, 3.0}));
  model.objects.push_back(room_reverb::test::woodCuboid("table", {2.0, 3.8, 0.4}, {1.2, 0.8, 0.8}));
  model.objects.push_back(room_reverb::test::woodCuboid("cabinet", {1.0, 1.0, 1.0}, {0.5, 0.6, 2.0}));
  const AcousticScene scene = roomModelToScene(model, MaterialLibrary::loadDefault(), {});
  const TriangleMesh& mesh = scene.mesh();
  const Eigen::Vector3d listener(3.0, 2.2, 1.3);
  const TriangleVisibility visibility(mesh, listener);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t partly = 0, clear = 0, settled = 0, hidden = 0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (visibility.seenWhole(t)) continue;
    ++partly;
    EXPECT_LT(visibility.seenShare(t), 1.0);
    const Eigen::Vector3d a = mesh.vertices[mesh.triangles[t][0]], b = mesh.vertices[mesh.triangles[t][1]],
                          c = mesh.vertices[mesh.triangles[t][2]];
    for (int i = 0; i < 300; ++i) {
      double u = unit(rng), v = unit(rng);
      if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
      }
      const Eigen::Vector3d point = a + u * (b - a) + v * (c - a);
      const bool blocked = scene.geometry().occluded(point, listener, 1e-5);
      const bool sees = visibility.sees(t, point);
      if (sees) {
        EXPECT_FALSE(blocked) << "triangle " << t << " at " << point.transpose();
      }
      if (blocked) {
        ++hidden;
      } else {
        ++clear;
        if (sees) ++settled;
      }
    }
  }
  EXPECT_GT(partly, 10u);
  EXPECT_GT(hidden, 1000u);  // the objects do hide some of the points
  EXPECT_GT(static_cast<double>(settled), 0.6 * static_cast<double>(clear));
  std::cout << "[          ] " << partly << " triangles partly hidden; of their points " << hidden << " hidden, " << clear
            << " clear, " << settled << " of those settled by the cells\n";
}
