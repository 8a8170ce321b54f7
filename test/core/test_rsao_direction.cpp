// Direction of arrival from first-order AmbiX by the steered cardioid (RSAO, Remaggi et al.
// 2.1): grid search as in the paper and the closed-form maximum, on plane waves whose
// direction is known.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/rsao/direction_of_arrival.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Eigen::Vector3d unitFromAngles(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Adds a plane wave from `direction` carrying `signal` to a first-order AmbiX buffer,
// encoded with the project's SN3D harmonics (ACN W, Y, Z, X).
void addPlaneWave(AudioBuffer& buffer, const Eigen::Vector3d& direction, const std::vector<double>& signal) {
  const auto y = sn3dHarmonics(1, direction);
  for (std::size_t c = 0; c < 4; ++c)
    for (std::size_t n = 0; n < signal.size(); ++n) buffer.channels[c][n] += static_cast<float>(y[c] * signal[n]);
}

std::vector<double> noise(std::size_t length, double scale, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, scale);
  std::vector<double> x(length);
  for (auto& v : x) v = normal(rng);
  return x;
}

SampleWindow wholeBuffer(std::size_t length) {
  SampleWindow w;
  w.weights.assign(length, 1.0);
  return w;
}

}  // namespace

TEST(DirectionOfArrival, AzimuthAndElevationFollowDesignConventions) {
  const auto check = [](const Eigen::Vector3d& v, double azimuth, double elevation) {
    const auto d = directionFromVector(v);
    EXPECT_NEAR(d.azimuth_rad, azimuth, 1e-12) << v.transpose();
    EXPECT_NEAR(d.elevation_rad, elevation, 1e-12) << v.transpose();
  };
  check({1, 0, 0}, 0.0, 0.0);
  check({0, 2, 0}, kPi / 2, 0.0);  // +y is left: counter-clockwise from +x
  check({0, -1, 0}, -kPi / 2, 0.0);
  check({-1, 0, 0}, -kPi, 0.0);  // [-pi, pi): behind is -pi, not +pi
  check({0, 0, 3}, 0.0, kPi / 2);
  check({1, 1, -std::sqrt(2.0)}, kPi / 4, -kPi / 4);
}

TEST(DirectionOfArrival, QuadraticFormEqualsTheSampleBySampleCardioidEnergy) {
  std::mt19937 rng(1);
  AudioBuffer b = makeSilentBuffer(4, 64, 48000.0);
  for (auto& channel : b.channels)
    for (auto& v : channel) v = static_cast<float>(std::normal_distribution<double>(0.0, 1.0)(rng));
  SampleWindow window;
  window.first = 10;
  for (int i = 0; i < 40; ++i) window.weights.push_back(0.3 + 0.01 * i);
  const auto stats = steeringStatistics(b, window);
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector3d v = unitFromAngles(0.37 * k - 3.0, 0.15 * k - 1.4);
    const double direct = steeredCardioidEnergy(b, window, v);
    EXPECT_NEAR(stats.steeredEnergy(v) / direct, 1.0, 1e-12);
  }
}

TEST(DirectionOfArrival, PlaneWavesAreFoundExactlyByTheClosedFormAndWithinAStepByTheGrid) {
  std::mt19937 rng(2);
  const std::vector<std::pair<double, double>> directions = {
      {0.0, 0.0}, {90 * kDeg, 0.0}, {-179.5 * kDeg, 3 * kDeg}, {37 * kDeg, 62 * kDeg},
      {-123 * kDeg, -41 * kDeg}, {10 * kDeg, 89.5 * kDeg}, {-75 * kDeg, -88 * kDeg}};
  for (const auto& [azimuth, elevation] : directions) {
    AudioBuffer b = makeSilentBuffer(4, 96, 48000.0);
    const Eigen::Vector3d u = unitFromAngles(azimuth, elevation);
    addPlaneWave(b, u, noise(96, 1.0, rng));
    const auto stats = steeringStatistics(b, wholeBuffer(96));
    const auto exact = directionClosedForm(stats);
    EXPECT_LT(angleBetween(exact.direction, u), 1e-5) << azimuth / kDeg << ", " << elevation / kDeg;
    EXPECT_NEAR(exact.elevation_rad, elevation, 1e-5);
    if (std::abs(elevation) < 80 * kDeg) {
      EXPECT_NEAR(exact.azimuth_rad, azimuth, 1e-5);
    }
    // The cardioid towards the source carries all of W's energy.
    EXPECT_NEAR(exact.steered_energy / stats.energy_w, 1.0, 1e-6);
    const auto grid = directionByGridSearch(stats, 1.0 * kDeg);
    EXPECT_LT(angleBetween(grid.direction, u), 1.0 * kDeg);
  }
}

TEST(DirectionOfArrival, ClosedFormAndGridAgreeWithinTheGridStepOnMixtures) {
  // A main plane wave, a second one 6 dB down from elsewhere and uncorrelated noise in
  // every channel at -20 dB: the maximum moves off either source, and both searches must
  // find the same one.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (double step_deg : {1.0, 3.0}) {
    for (int trial = 0; trial < 30; ++trial) {
      const std::size_t n = 96;
      AudioBuffer b = makeSilentBuffer(4, n, 48000.0);
      const Eigen::Vector3d u1 = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)).normalized();
      const Eigen::Vector3d u2 = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)).normalized();
      addPlaneWave(b, u1, noise(n, 1.0, rng));
      addPlaneWave(b, u2, noise(n, 0.5, rng));
      for (auto& channel : b.channels) {
        const auto floor = noise(n, 0.1, rng);
        for (std::size_t i = 0; i < n; ++i) channel[i] += static_cast<float>(floor[i]);
      }
      const auto stats = steeringStatistics(b, wholeBuffer(n));
      const auto exact = directionClosedForm(stats);
      const auto grid = directionByGridSearch(stats, step_deg * kDeg);
      EXPECT_LT(angleBetween(exact.direction, grid.direction), step_deg * kDeg) << "trial " << trial;
      // The closed form is the true maximum: no grid point beats it.
      EXPECT_GE(exact.steered_energy, grid.steered_energy * (1.0 - 1e-12));
    }
  }
}

TEST(DirectionOfArrival, HardCaseOfTheSecularEquation) {
  // p has no component along R's top eigenvector (z) and is short, so the maximum sits at
  // lambda = mu_max: v = (p_x / (mu_max - mu_x), 0, +-sqrt(1 - v_x^2)).
  CardioidSteeringStatistics stats;
  stats.energy_w = 1.0;
  stats.covariance = Eigen::Vector3d(1.0, 2.0, 5.0).asDiagonal();
  stats.w_cross = Eigen::Vector3d(0.5, 0.0, 0.0);
  const auto d = directionClosedForm(stats);
  const double vx = 0.5 / 4.0;
  EXPECT_NEAR(d.direction.x(), vx, 1e-12);
  EXPECT_NEAR(d.direction.y(), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(d.direction.z()), std::sqrt(1.0 - vx * vx), 1e-12);
  const auto grid = directionByGridSearch(stats, 0.5 * kDeg);
  EXPECT_GE(d.steered_energy, grid.steered_energy * (1.0 - 1e-12));
  // Nearly the hard case: a part along z too small for the secular root to be told from
  // mu_max in double precision; the answer is the hard case's, on the side of that part.
  stats.w_cross = Eigen::Vector3d(0.5, 0.0, -1e-14);
  const auto near = directionClosedForm(stats);
  EXPECT_NEAR(near.direction.x(), vx, 1e-9);
  EXPECT_NEAR(near.direction.z(), -std::sqrt(1.0 - vx * vx), 1e-9);
  // Same zero component along z but a long p: the ordinary root lambda = 11 > mu_max.
  stats.w_cross = Eigen::Vector3d(10.0, 0.0, 0.0);
  EXPECT_LT(angleBetween(directionClosedForm(stats).direction, Eigen::Vector3d::UnitX()), 1e-9);
  // No p at all: the top eigenvector.
  stats.w_cross.setZero();
  EXPECT_NEAR(std::abs(directionClosedForm(stats).direction.z()), 1.0, 1e-12);
}

TEST(DirectionOfArrival, AmbixChannelOrderIsRespected) {
  // Energy only in ACN 1 (Y) in phase with W: the source is to the left (+y), azimuth +90.
  AudioBuffer b = makeSilentBuffer(4, 8, 48000.0);
  for (std::size_t n = 0; n < 8; ++n) b.channels[0][n] = b.channels[1][n] = (n % 2 ? 1.0f : -0.5f);
  auto d = directionClosedForm(steeringStatistics(b, wholeBuffer(8)));
  EXPECT_NEAR(d.azimuth_rad, kPi / 2, 1e-9);
  EXPECT_NEAR(d.elevation_rad, 0.0, 1e-9);
  // ACN 2 (Z) in phase with W: from above; ACN 3 (X) in antiphase: from behind.
  b = makeSilentBuffer(4, 8, 48000.0);
  for (std::size_t n = 0; n < 8; ++n) b.channels[0][n] = b.channels[2][n] = 1.0f;
  EXPECT_NEAR(directionClosedForm(steeringStatistics(b, wholeBuffer(8))).elevation_rad, kPi / 2, 1e-9);
  b = makeSilentBuffer(4, 8, 48000.0);
  for (std::size_t n = 0; n < 8; ++n) {
    b.channels[0][n] = 1.0f;
    b.channels[3][n] = -1.0f;
  }
  EXPECT_NEAR(directionClosedForm(steeringStatistics(b, wholeBuffer(8))).azimuth_rad, -kPi, 1e-9);
}

TEST(DirectionOfArrival, SphereGridIsNearUniformAndCoversTheSphere) {
  const double step = 1.0 * kDeg;
  const auto grid = sphereGrid(step);
  EXPECT_EQ(grid.size(), 41253u);  // ceil(4 pi / step^2)
  for (const auto& g : grid) EXPECT_NEAR(g.norm(), 1.0, 1e-12);
  // Any direction has a grid point within half a step or so (the covering radius);
  // checked on a coarser grid to keep the brute force small.
  const double coarse = 5.0 * kDeg;
  const auto points = sphereGrid(coarse);
  std::mt19937 rng(8);
  std::normal_distribution<double> normal(0.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d u = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    double nearest = kPi;
    for (const auto& g : points) nearest = std::min(nearest, angleBetween(u, g));
    worst = std::max(worst, nearest);
  }
  EXPECT_LT(worst, 0.75 * coarse);
  EXPECT_GT(worst, 0.3 * coarse);  // and the grid is not needlessly dense
}

TEST(DirectionOfArrival, ClosedFormIsMuchFasterThanTheGrid) {
  std::mt19937 rng(6);
  AudioBuffer b = makeSilentBuffer(4, 96, 48000.0);
  addPlaneWave(b, unitFromAngles(0.4, 0.2), noise(96, 1.0, rng));
  const auto stats = steeringStatistics(b, wholeBuffer(96));
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  double sink = 0.0;
  for (int i = 0; i < 2000; ++i) sink += directionClosedForm(stats).steered_energy;
  const auto t1 = Clock::now();
  for (int i = 0; i < 2; ++i) sink += directionByGridSearch(stats, 1.0 * kDeg).steered_energy;
  const auto t2 = Clock::now();
  const double closed_s = std::chrono::duration<double>(t1 - t0).count() / 2000;
  const double grid_s = std::chrono::duration<double>(t2 - t1).count() / 2;
  EXPECT_GT(sink, 0.0);
  EXPECT_LT(closed_s * 100.0, grid_s) << "closed form " << closed_s * 1e6 << " us, grid " << grid_s * 1e6 << " us";
}

TEST(DirectionOfArrival, BadInputIsAClearError) {
  const AudioBuffer three = makeSilentBuffer(3, 10, 48000.0);
  expectInputError([&] { steeringStatistics(three, wholeBuffer(10)); }, {"4 channels", "got 3"});
  expectInputError([] { sphereGrid(0.0); }, {"grid step"});
  expectInputError([] { sphereGrid(1.0); }, {"grid step"});
}
