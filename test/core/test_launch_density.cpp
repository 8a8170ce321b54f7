// Importance sampling of launch directions (launch_density.h): equal-area cells, draws
// that follow a density with the weights that undo it, and rays launched from a density
// whose every energy keeps its expectation.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "room_reverb/acoustics/launch_density.h"
#include "room_reverb/acoustics/ray_tracer.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/common/error.h"
#include "shoebox.h"
#include "test_rooms.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

// A density that puts most of its rays near the horizon, as a room with an absorbing floor
// and ceiling asks for: the four middle zones 20 times the others' weight.
LaunchDensity horizonDensity() {
  std::array<double, kLaunchCells> weights{};
  for (int c = 0; c < kLaunchCells; ++c) {
    const int zone = c / kLaunchSectors;
    weights[static_cast<std::size_t>(c)] = std::abs(zone - kLaunchZones / 2 + 0.5) < 2.0 ? 20.0 : 1.0;
  }
  return LaunchDensity(weights);
}

TEST(LaunchDensity, TheCellsHaveEqualAreas) {
  // A Fibonacci sphere of 256 000 points (uniform on the sphere): each cell holds 1/256.
  const int n = 256000;
  std::array<int, kLaunchCells> count{};
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double turns = i * 0.61803398874989484820;
    const double phi = 2.0 * M_PI * (turns - std::floor(turns)), r = std::sqrt(1.0 - z * z);
    ++count[static_cast<std::size_t>(launchCellOf({r * std::cos(phi), r * std::sin(phi), z}))];
  }
  for (int c = 0; c < kLaunchCells; ++c) EXPECT_NEAR(count[static_cast<std::size_t>(c)], n / kLaunchCells, 40) << c;
  EXPECT_EQ(launchCellOf({0.0, 0.0, 1.0}), 0);
  EXPECT_EQ(launchCellOf({0.0, 0.0, -1.0}) / kLaunchSectors, kLaunchZones - 1);
  EXPECT_EQ(launchCellOf({1.0, 0.0, 0.0}) % kLaunchSectors, 0);
  EXPECT_EQ(launchCellOf({0.0, -1.0, 0.0}) % kLaunchSectors, kLaunchSectors * 3 / 4);
}

TEST(LaunchDensity, DrawsFollowTheDensityWithWeightsThatUndoIt) {
  const LaunchDensity density = horizonDensity();
  const int nu = 4096, nv = 64;
  std::array<double, kLaunchCells> share{};
  double weight_sum = 0.0;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const LaunchDensity::Draw draw = density.draw((i + 0.5) / nu, (j + 0.5) / nv);
      ASSERT_NEAR(draw.direction.norm(), 1.0, 1e-12);
      const int cell = launchCellOf(draw.direction);
      share[static_cast<std::size_t>(cell)] += 1.0 / (nu * nv);
      // The weight is the uniform density over the cell's: 1 / (cells p).
      ASSERT_NEAR(draw.weight, 1.0 / (kLaunchCells * density.probabilities()[static_cast<std::size_t>(cell)]), 1e-9);
      weight_sum += draw.weight / (nu * nv);
    }
  }
  for (int c = 0; c < kLaunchCells; ++c) {
    EXPECT_NEAR(share[static_cast<std::size_t>(c)], density.probabilities()[static_cast<std::size_t>(c)], 2e-4) << c;
  }
  // The weights' mean is 1: the rays together carry the whole emission.
  EXPECT_NEAR(weight_sum, 1.0, 1e-3);
  // The uniform density draws every direction at weight 1.
  const LaunchDensity uniform;
  EXPECT_DOUBLE_EQ(uniform.draw(0.3, 0.7).weight, 1.0);
}

TEST(LaunchDensity, TheDefensiveMixtureBoundsTheWeights) {
  std::array<double, kLaunchCells> late{};
  late[100] = 1.0;  // all the late energy launched in one cell
  const LaunchDensity density = lateEnergyDensity(late, 0.5);
  EXPECT_NEAR(density.probabilities()[100], 0.5 + 0.5 / kLaunchCells, 1e-12);
  for (double p : density.probabilities()) EXPECT_LE(1.0 / (kLaunchCells * p), 2.0 + 1e-12);
  EXPECT_THROW(lateEnergyDensity(late, 1.0), InputError);
  EXPECT_THROW(lateEnergyDensity(late, -0.1), InputError);
  late[3] = 0.5;  // sums to 1.5
  EXPECT_THROW(lateEnergyDensity(late, 0.5), InputError);
  late[3] = -0.5;
  late[100] = 1.5;
  EXPECT_THROW(lateEnergyDensity(late, 0.5), InputError);
  std::array<double, kLaunchCells> weights{};
  weights.fill(1.0);
  weights[7] = 0.0;
  EXPECT_THROW(LaunchDensity{weights}, InputError);
  weights[7] = std::nan("");
  EXPECT_THROW(LaunchDensity{weights}, InputError);
  // Another density's probabilities are taken exactly, and must sum to 1.
  const LaunchDensity again = LaunchDensity::fromProbabilities(density.probabilities());
  EXPECT_EQ(again.probabilities(), density.probabilities());
  std::array<double, kLaunchCells> half{};
  half.fill(0.5 / kLaunchCells);
  EXPECT_THROW(LaunchDensity::fromProbabilities(half), InputError);
}

// The same room traced with uniform launches and with most rays near the horizon: the
// energy at the receiver in windows of the decay, and what the rays still carry at the end
// in a lossless room, agree within the two runs' noise: weighting undoes the density.
TEST(LaunchDensity, RaysFromADensityKeepEveryEnergysExpectation) {
  const AcousticScene scene = roomModelToScene(unevenAbsorptionRoom(), MaterialLibrary::loadDefault(), {});
  const Eigen::Vector3d source(1.8, 1.6, 1.5), listener(5.1, 3.4, 1.3);
  const PropagationModel model = PropagationModel::from(AirConditions{}, {});
  RayTracingOptions options;
  options.ray_count = 20000;
  options.max_time_s = 0.6;
  options.track_radius_m = 1.5;
  options.continue_established_decays = false;
  options.threads = 2;
  const auto windowEnergy = [](const EnergyHistogram& h, int band, double from_s, double to_s) {
    double e = 0.0;
    for (auto k = static_cast<std::size_t>(from_s / h.binS()); k < static_cast<std::size_t>(to_s / h.binS()); ++k) e += h.energy(k, band);
    return e;
  };
  double uniform_early = 0.0, uniform_late = 0.0, dense_early = 0.0, dense_late = 0.0;
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    options.seed = seed;
    options.launch_density = nullptr;
    const RayTracingResult uniform = traceRays(scene, source, listener, model, options);
    options.launch_density = std::make_shared<LaunchDensity>(horizonDensity());
    const RayTracingResult dense = traceRays(scene, source, listener, model, options);
    for (int band : {2, 4, 6}) {
      uniform_early += windowEnergy(uniform.histogram, band, 0.02, 0.1);
      dense_early += windowEnergy(dense.histogram, band, 0.02, 0.1);
      uniform_late += windowEnergy(uniform.histogram, band, 0.2, 0.6);
      dense_late += windowEnergy(dense.histogram, band, 0.2, 0.6);
    }
  }
  std::printf("[ measured ] horizon density over uniform launches: 20-100 ms %.3f, 200-600 ms %.3f\n",
              dense_early / uniform_early, dense_late / uniform_late);
  EXPECT_NEAR(dense_early / uniform_early, 1.0, 0.04);
  EXPECT_NEAR(dense_late / uniform_late, 1.0, 0.08);

  // Lossless: every ray keeps its energy to the end, so the rays' weights must sum to the
  // emission.
  const AcousticScene lossless(shoeboxMesh({6, 4, 3}), uniformLibrary(0.0, 0.1));
  RayTracingOptions kept = options;
  kept.max_time_s = 0.1;
  kept.launch_density = std::make_shared<LaunchDensity>(horizonDensity());
  PropagationModel no_air = PropagationModel::from(AirConditions{}, {});
  no_air.air_attenuation_per_m.fill(0.0);
  const RayTracingResult no_air_traced = traceRays(lossless, {1.5, 1.2, 1.4}, {4.2, 3.1, 1.3}, no_air, kept);
  EXPECT_NEAR(no_air_traced.stats.energy_left_at_time_limit[4], 1.0, 0.01);
}

}  // namespace
}  // namespace room_reverb::test
