// The fast mode's rays in batches (fast_mode_rays.h): a band's decay rate from its energy
// in flight, and a pilot of batches that is the decay in a diffuse room and gives way to
// one run of every ray, or of what a budget of reflections buys, where the sound rides on
// a few grazing paths.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "room_reverb/acoustics/fast_mode_rays.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/sample_statistics.h"
#include "shoebox.h"
#include "test_rooms.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

std::vector<OctaveBandValues> exponentialEnergy(double tau_s, std::size_t bins, double bin_s) {
  std::vector<OctaveBandValues> e(bins);
  for (std::size_t bin = 0; bin < bins; ++bin) e[bin].fill(std::exp(-(static_cast<double>(bin) + 0.5) * bin_s / tau_s));
  return e;
}

TEST(FastModeRays, TheRateOfAnExponentialIsItsSlopeInDecibels) {
  const double tau = 0.1;  // 43.4 dB/s
  const auto rate = energyDecayRateDbPerS(exponentialEnergy(tau, 2000, 0.001), 3, 0.001);
  ASSERT_TRUE(rate);
  EXPECT_NEAR(*rate, -10.0 / std::log(10.0) / tau, 1e-9);
  // Falling only 12 dB in the trace: 5-12 dB is too short a line to go by.
  EXPECT_FALSE(energyDecayRateDbPerS(exponentialEnergy(tau, 320, 0.001), 3, 0.001));
  // 20 dB: the line from 5 dB down to the lowest level is used.
  const auto short_rate = energyDecayRateDbPerS(exponentialEnergy(tau, 460, 0.001), 3, 0.001);
  ASSERT_TRUE(short_rate);
  EXPECT_NEAR(*short_rate, -10.0 / std::log(10.0) / tau, 1e-9);
  EXPECT_FALSE(energyDecayRateDbPerS({}, 3, 0.001));
  std::vector<OctaveBandValues> silent(100, OctaveBandValues{});
  EXPECT_FALSE(energyDecayRateDbPerS(silent, 3, 0.001));
}

struct Traced {
  FastModeTrace trace;
  double rate_1k = 0.0;  // dB/s: of the energy in flight when the pilot settled, else of the receiver
};

// The decay rate (dB/s) of a histogram's band: the least-squares line through the levels
// of its 10 ms windows from `from_s` to `to_s`.
double receiverRateDbPerS(const EnergyHistogram& h, int band, double from_s, double to_s) {
  std::vector<double> t, level;
  const auto window = static_cast<std::size_t>(std::lround(0.01 / h.binS()));
  for (auto k = static_cast<std::size_t>(from_s / h.binS()); k + window <= static_cast<std::size_t>(to_s / h.binS()); k += window) {
    double e = 0.0;
    for (std::size_t i = k; i < k + window; ++i) e += h.energy(i, band);
    t.push_back((static_cast<double>(k) + 0.5 * static_cast<double>(window)) * h.binS());
    level.push_back(10.0 * std::log10(e));
  }
  const double mt = sampleMean(t), ml = sampleMean(level);
  double stl = 0.0, stt = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    stl += (t[i] - mt) * (level[i] - ml);
    stt += (t[i] - mt) * (t[i] - mt);
  }
  return stl / stt;
}

Traced trace(const AcousticScene& scene, const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
             std::size_t max_rays, const FastRayOptions& options, std::uint32_t seed) {
  RayTracingOptions rays;
  rays.max_time_s = 1.5;
  rays.record_energy_in_flight = true;
  rays.diffuse_rain = false;
  rays.roulette_db = -40.0;
  rays.seed = seed;
  Traced t;
  t.trace = traceFastModeDecay(scene, source, listener, PropagationModel::from(AirConditions{}, {}), rays, max_rays,
                               options);
  t.rate_1k = t.trace.receiver ? receiverRateDbPerS(*t.trace.receiver, 4, 0.1, 0.6)
                               : *energyDecayRateDbPerS(t.trace.energy_in_flight, 4, rays.bin_s);
  return t;
}

TEST(FastModeRays, ADiffuseRoomStopsAtTheLeastRaysAndKeepsItsRate) {
  // A shoebox whose walls scatter half of what they reflect: every ray sees every wall.
  const AcousticScene scene(shoeboxMesh({6, 5, 3}), uniformLibrary(0.15, 0.5));
  const Eigen::Vector3d source(1.5, 1.2, 1.4), listener(4.2, 3.1, 1.3);
  const FastRayOptions options;
  const Traced adaptive = trace(scene, source, listener, 32000, options, 1);
  FastRayOptions fixed;
  fixed.rate_tolerance = 0.0;
  const Traced all = trace(scene, source, listener, 32000, fixed, 1);
  std::cout << "[ measured ] diffuse room: " << adaptive.trace.stats.rays << " rays in " << adaptive.trace.batches
            << " batches; 1 kHz rate " << adaptive.rate_1k << " dB/s in flight, " << all.rate_1k
            << " dB/s at the receiver from 32000\n";
  EXPECT_EQ(adaptive.trace.stats.rays, options.min_rays);
  EXPECT_EQ(adaptive.trace.batches, options.min_rays / options.batch_rays);
  EXPECT_EQ(all.trace.stats.rays, 32000u);
  EXPECT_EQ(all.trace.batches, 1u);
  // The room's mean decay, from the pilot, is the decay at the listener.
  EXPECT_NEAR(adaptive.rate_1k / all.rate_1k, 1.0, 0.03);
}

TEST(FastModeRays, GrazingPathsBetweenAnAbsorbingFloorAndCeilingTakeEveryRay) {
  // The decay that lasts is carried by the few rays that travel between the walls.
  const AcousticScene scene = roomModelToScene(unevenAbsorptionRoom(), MaterialLibrary::loadDefault(), {});
  const Eigen::Vector3d source(1.8, 1.6, 1.5), listener(5.1, 3.4, 1.3);
  FastRayOptions uniform;
  uniform.late_launch_mixture = 0.0;
  const Traced adaptive = trace(scene, source, listener, 8000, uniform, 1);
  FastRayOptions fixed;
  fixed.rate_tolerance = 0.0;
  const Traced all = trace(scene, source, listener, 8000, fixed, 1);
  std::cout << "[ measured ] grazing room: " << adaptive.trace.stats.rays << " rays in " << adaptive.trace.batches
            << " batches\n";
  // The pilot did not know the rates: every ray in one run, launched uniformly, exactly
  // what a fixed count gives.
  EXPECT_FALSE(adaptive.trace.launch_density);
  EXPECT_EQ(adaptive.trace.stats.rays, 8000u);
  EXPECT_EQ(adaptive.trace.batches, 1u);
  ASSERT_TRUE(adaptive.trace.receiver && all.trace.receiver);
  EXPECT_TRUE(adaptive.trace.energy_in_flight.empty());
  ASSERT_EQ(adaptive.trace.receiver->bins(), all.trace.receiver->bins());
  for (std::size_t bin = 0; bin < all.trace.receiver->bins(); bin += 97) {
    EXPECT_EQ(adaptive.trace.receiver->energy(bin, 4), all.trace.receiver->energy(bin, 4)) << bin;
  }
  // At most the rays asked for: with fewer than the pilot's, they are the one run.
  const Traced few = trace(scene, source, listener, 1500, FastRayOptions{}, 1);
  EXPECT_EQ(few.trace.stats.rays, 1500u);
  EXPECT_EQ(few.trace.batches, 1u);
  // A budget of reflections below what the rays asked for would cost: as many rays as it
  // buys at the pilot's reflections per ray, which the run itself then about spends.
  FastRayOptions budget;
  budget.reflection_budget = 3.0e5;
  const Traced bought = trace(scene, source, listener, 64000, budget, 1);
  const double per_ray = static_cast<double>(bought.trace.stats.reflections) / static_cast<double>(bought.trace.stats.rays);
  std::cout << "[ measured ] grazing room, 3e5 reflections: " << bought.trace.stats.rays << " rays, " << per_ray
            << " reflections per ray\n";
  EXPECT_EQ(bought.trace.batches, 1u);
  EXPECT_GT(bought.trace.stats.rays, budget.min_rays);
  EXPECT_LT(bought.trace.stats.rays, 64000u);
  EXPECT_NEAR(static_cast<double>(bought.trace.stats.reflections) / budget.reflection_budget, 1.0, 0.15);
}

// The run after an unsettled pilot launches half its rays where the pilot's late energy
// was launched: in a room whose floor and ceiling absorb, near the horizon.
TEST(FastModeRays, TheRunLaunchesWhereThePilotsLateEnergyWasLaunched) {
  const AcousticScene scene = roomModelToScene(unevenAbsorptionRoom(), MaterialLibrary::loadDefault(), {});
  const Traced run = trace(scene, {1.8, 1.6, 1.5}, {5.1, 3.4, 1.3}, 8000, FastRayOptions{}, 1);
  ASSERT_TRUE(run.trace.launch_density);
  const auto& p = run.trace.launch_density->probabilities();
  double horizon = 0.0, top = 0.0, heaviest = 0.0;  // within 15 degrees of horizontal; steeper than 60 degrees up
  for (int c = 0; c < kLaunchCells; ++c) {
    const double z = 1.0 - 2.0 * (c / kLaunchSectors + 0.5) / kLaunchZones;
    if (std::abs(z) < std::sin(15.0 * M_PI / 180.0)) horizon += p[static_cast<std::size_t>(c)];
    if (z > std::sin(60.0 * M_PI / 180.0)) top += p[static_cast<std::size_t>(c)];
    heaviest = std::max(heaviest, 1.0 / (kLaunchCells * p[static_cast<std::size_t>(c)]));
  }
  std::cout << "[ measured ] grazing room's launch density: " << 100.0 * horizon << " % within 15 degrees of the horizon (uniform "
            << 100.0 * std::sin(15.0 * M_PI / 180.0) << " %), " << 100.0 * top << " % above 60 degrees\n";
  EXPECT_GT(horizon, 1.5 * std::sin(15.0 * M_PI / 180.0));
  EXPECT_LT(top, 0.9 * 0.5 * (1.0 - std::sin(60.0 * M_PI / 180.0)));
  EXPECT_LE(heaviest, 2.0 + 1e-9);  // the defensive half bounds every ray's weight
  // A settled pilot launches nothing more.
  const AcousticScene diffuse(shoeboxMesh({6, 5, 3}), uniformLibrary(0.15, 0.5));
  EXPECT_FALSE(trace(diffuse, {1.5, 1.2, 1.4}, {4.2, 3.1, 1.3}, 32000, FastRayOptions{}, 1).trace.launch_density);
}

TEST(FastModeRays, BadCountsAreClearErrors) {
  const AcousticScene scene(shoeboxMesh({5, 4, 3}), uniformLibrary(0.2, 0.2));
  RayTracingOptions rays;
  rays.record_energy_in_flight = true;
  const PropagationModel model = PropagationModel::from(AirConditions{}, {});
  EXPECT_THROW(traceFastModeDecay(scene, {1, 1, 1}, {3, 2, 1}, model, rays, 0, FastRayOptions{}), InputError);
  FastRayOptions no_batch;
  no_batch.batch_rays = 0;
  EXPECT_THROW(traceFastModeDecay(scene, {1, 1, 1}, {3, 2, 1}, model, rays, 5000, no_batch), InputError);
  FastRayOptions no_budget;
  no_budget.reflection_budget = 0.0;
  EXPECT_THROW(traceFastModeDecay(scene, {1, 1, 1}, {3, 2, 1}, model, rays, 5000, no_budget), InputError);
  for (double mixture : {-0.1, 1.0, std::nan("")}) {
    FastRayOptions bad_mixture;
    bad_mixture.late_launch_mixture = mixture;
    EXPECT_THROW(traceFastModeDecay(scene, {1, 1, 1}, {3, 2, 1}, model, rays, 5000, bad_mixture), InputError);
  }
  for (double radius : {0.0, -2.0, std::nan("")}) {
    FastRayOptions no_track;
    no_track.track_radius_m = radius;
    EXPECT_THROW(traceFastModeDecay(scene, {1, 1, 1}, {3, 2, 1}, model, rays, 5000, no_track), InputError);
  }
}

}  // namespace
}  // namespace room_reverb::test
