// Continuing an established decay analytically (decay_continuation.h): the line is found
// only where the energy in flight has fallen far and runs straight, and the ray tracer
// that stops there gives the late energy it would have traced, with fewer reflections;
// where the decay bends it traces on.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "room_reverb/acoustics/decay_continuation.h"
#include "room_reverb/acoustics/ray_tracer.h"
#include "shoebox.h"

using namespace room_reverb::core;

namespace {

constexpr double kBinS = 0.005;

std::vector<double> sampled(double duration_s, const std::function<double(double)>& energy) {
  std::vector<double> e;
  for (double t = 0.5 * kBinS; t < duration_s; t += kBinS) e.push_back(energy(t));
  return e;
}

double windowEnergy(const EnergyHistogram& h, int band, double from_s, double to_s) {
  double sum = 0.0;
  for (auto k = static_cast<std::size_t>(from_s / h.binS()); k < static_cast<std::size_t>(to_s / h.binS()); ++k) sum += h.energy(k, band);
  return sum;
}

AirConditions noAir() {
  AirConditions air;
  air.enabled = false;
  return air;
}

}  // namespace

TEST(DecayContinuation, AStraightDecayIsEstablishedOnceItHasFallenFarEnough) {
  const double rate = -6.0 * std::log(10.0) / 0.8;  // T60 0.8 s: 25 dB at 0.33 s
  const std::vector<double> e = sampled(2.0, [&](double t) { return std::exp(rate * t); });
  const DecayContinuationOptions options;
  EXPECT_FALSE(establishedDecay(e, static_cast<std::size_t>(0.3 / kBinS), kBinS, options));
  const auto line = establishedDecay(e, static_cast<std::size_t>(0.45 / kBinS), kBinS, options);
  ASSERT_TRUE(line);
  EXPECT_NEAR(line->rate_per_s / rate, 1.0, 1e-6);
  EXPECT_NEAR(line->energyAt(1.5) / std::exp(rate * 1.5), 1.0, 1e-6);
  // The last 15 dB run from 0.25 s to 0.45 s; the line is their later half's.
  EXPECT_NEAR(line->fitted_from_s, 0.35, kBinS);
}

// Two decays, the slower 20 dB under the faster at the start (T60 0.5 s and 2 s): the sum
// bends where the slower takes over, about 30 dB down, and only a stretch well past the
// bend is straight enough to continue.
TEST(DecayContinuation, ABentDecayIsNotEstablishedUntilItRunsStraight) {
  const double fast = -6.0 * std::log(10.0) / 0.5, slow = -6.0 * std::log(10.0) / 2.0;
  const std::vector<double> e = sampled(3.0, [&](double t) { return std::exp(fast * t) + 0.01 * std::exp(slow * t); });
  const DecayContinuationOptions options;
  double established_at = 0.0;
  for (std::size_t n = 8; n <= e.size(); ++n) {
    if (const auto line = establishedDecay(e, n, kBinS, options)) {
      established_at = static_cast<double>(n) * kBinS;
      EXPECT_NEAR(line->rate_per_s / slow, 1.0, 0.1);
      break;
    }
  }
  std::cout << "[ measured ] established at " << established_at << " s\n";
  EXPECT_GT(established_at, 0.6);
}

TEST(DecayContinuation, NoLineThroughEmptyOrRisingEnergy) {
  const DecayContinuationOptions options;
  EXPECT_FALSE(establishedDecay(std::vector<double>(100, 0.0), 100, kBinS, options));
  EXPECT_FALSE(establishedDecay(std::vector<double>(100, 1.0), 100, kBinS, options));
  EXPECT_FALSE(establishedDecay(std::vector<double>(3, 1.0), 50, kBinS, options));
}

// A room whose walls scatter: the decay is straight, the bands stop early, and the late
// energy at the receiver is what tracing to the end gives, with far fewer reflections.
TEST(DecayContinuation, TheTracerStopsAStraightDecayEarlyAndKeepsItsLateEnergy) {
  const Eigen::Vector3d size(7, 5, 3), source(1.5, 1.2, 1.4), listener(5.2, 3.4, 1.6);
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.15, 0.5));
  const PropagationModel model = PropagationModel::from(noAir(), {});
  RayTracingOptions options = room_reverb::test::twoThreads(6000, 1.0);
  const RayTracingResult continued = traceRays(scene, source, listener, model, options);
  options.continue_established_decays = false;
  const RayTracingResult traced = traceRays(scene, source, listener, model, options);
  const double share = static_cast<double>(continued.stats.reflections) / static_cast<double>(traced.stats.reflections);
  std::cout << "[ measured ] stopped at " << continued.stats.traced_until_s[4] << " s, reflections " << share << " of tracing to the end\n";
  EXPECT_LT(continued.stats.traced_until_s[4], 1.0);
  EXPECT_LT(share, 0.7);
  const double windows[][2] = {{0.1, 0.3}, {0.3, 0.6}, {0.6, 1.0}};
  for (const auto& w : windows) {
    const double ratio = windowEnergy(continued.histogram, 4, w[0], w[1]) / windowEnergy(traced.histogram, 4, w[0], w[1]);
    std::cout << "[ measured ] " << w[0] << "-" << w[1] << " s: " << ratio << "\n";
    EXPECT_NEAR(ratio, 1.0, 0.1) << w[0] << "-" << w[1] << " s";
  }
}

// A slowly decaying room whose 1 kHz band (absorption 0.05) falls 25 dB near 1 s, after
// the octaves above it (0.07) have fallen as far and stopped near 0.7 s. A slice ends when
// the first band still traced is predicted to have fallen that far, so the 1 kHz band too
// stops within one slice (25 ms) and a flight bin of it, not a quarter of the elapsed
// time later, while every branch would go on reflecting.
TEST(DecayContinuation, ABandStopsWithinASliceOfItsOwnTwentyFiveDecibels) {
  const Eigen::Vector3d size(7, 5, 3), source(1.5, 1.2, 1.4), listener(5.2, 3.4, 1.6);
  AcousticMaterial wall = room_reverb::test::uniformLibrary(0.05, 0.5).get("test_wall");
  for (int b = 5; b < kOctaveBandCount; ++b) wall.absorption[b] = 0.07;
  MaterialLibrary library;
  library.add(wall);
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), library);
  const PropagationModel model = PropagationModel::from(noAir(), {});
  RayTracingOptions options = room_reverb::test::twoThreads(3000, 2.5);
  const RayTracingResult continued = traceRays(scene, source, listener, model, options);
  options.continue_established_decays = false;
  options.record_energy_in_flight = true;
  const RayTracingResult traced = traceRays(scene, source, listener, model, options);
  double fallen_at_s = 0.0;
  for (std::size_t k = 0; k < traced.energy_in_flight.size(); ++k) {
    if (traced.energy_in_flight[k][4] < traced.energy_in_flight[0][4] * std::pow(10.0, -2.5)) {
      fallen_at_s = (static_cast<double>(k) + 0.5) * options.bin_s;
      break;
    }
  }
  std::cout << "[ measured ] 25 dB down at " << fallen_at_s << " s, stopped at " << continued.stats.traced_until_s[4]
            << " s (2 kHz at " << continued.stats.traced_until_s[5] << " s)\n";
  EXPECT_GT(fallen_at_s, 0.6);
  EXPECT_LT(continued.stats.traced_until_s[5], fallen_at_s - 0.15);
  EXPECT_GT(continued.stats.traced_until_s[4], fallen_at_s - 0.01);
  EXPECT_LT(continued.stats.traced_until_s[4], fallen_at_s + 0.035);
}

// A low room (1 m) with a nearly black floor and ceiling between mirror-like walls: a ray
// at elevation e loses its energy at a rate that grows with sin e, so the energy in flight
// falls as 1 / t, a decay that bends all the way. The tracer must trace on past the first
// 25 dB.
TEST(DecayContinuation, TheTracerTracesABentDecayOn) {
  const Eigen::Vector3d size(8, 6, 1), source(1.5, 1.2, 0.4), listener(6.2, 4.4, 0.6);
  TriangleMesh mesh = room_reverb::test::shoeboxMesh(size);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const double nz = std::abs(mesh.normal(t).z());
    if (nz > 0.9) mesh.triangle_material[t] = mesh.materialIndex("absorber");
  }
  MaterialLibrary library = room_reverb::test::uniformLibrary(0.02, 0.0);
  library.add(room_reverb::test::uniformLibrary(0.99, 0.0, "absorber").get("absorber"));
  const AcousticScene scene(mesh, library);
  const PropagationModel model = PropagationModel::from(noAir(), {});
  RayTracingOptions options = room_reverb::test::twoThreads(30000, 2.2);
  options.continue_established_decays = false;
  const RayTracingResult traced = traceRays(scene, source, listener, model, options);
  options.continue_established_decays = true;
  const RayTracingResult continued = traceRays(scene, source, listener, model, options);
  options.continuation.bend_db = 1e9;
  options.continuation.scatter_db = 1e9;
  const RayTracingResult unchecked = traceRays(scene, source, listener, model, options);
  std::cout << "[ measured ] traced until " << continued.stats.traced_until_s[4] << " s (unchecked "
            << unchecked.stats.traced_until_s[4] << " s)\n";
  const double late[2] = {1.4, 2.1};
  const double ratio = windowEnergy(continued.histogram, 4, late[0], late[1]) / windowEnergy(traced.histogram, 4, late[0], late[1]);
  std::cout << "[ measured ] 1.4-2.1 s energy over tracing to the end: " << ratio << "\n";
  EXPECT_EQ(continued.stats.traced_until_s[4], options.max_time_s);
  EXPECT_NEAR(ratio, 1.0, 0.1);
  // Without the checks of its shape the band stops once it has fallen 25 dB.
  EXPECT_LT(unchecked.stats.traced_until_s[4], 0.8 * options.max_time_s);
}
