#include <gtest/gtest.h>

#include <cmath>

#include "room_reverb/metrics/energy_decay.h"
#include "synthetic_rir.h"

using namespace room_reverb::core;
using room_reverb::test::kFs;

TEST(Lundeby, FindsTheCrosspointOfADecayInNoise) {
  // Mean-square 1 decaying at 60 dB/s (T = 1 s) meets noise at -50 dB after 0.833 s.
  std::vector<float> rir = room_reverb::test::exponentialDecayNoise(3 * 48000, 1.0, 0, 11);
  room_reverb::test::addNoiseFloor(rir, -50.0, 12);
  const EnergyDecay decay(rir, 0, kFs);
  ASSERT_TRUE(decay.valid()) << decay.lundeby().failure;
  EXPECT_NEAR(decay.lundeby().crosspoint / kFs, 50.0 / 60.0, 0.06);
  EXPECT_NEAR(decay.lundeby().noise_db, -50.0, 0.5);
  EXPECT_NEAR(decay.lundeby().slope_db_per_s, -60.0, 3.0);
  EXPECT_NEAR(decay.decayRangeDb(), 50.0, 1.5);
}

TEST(EnergyDecay, CompensatedCurveFollowsTheTrueDecayBelowTheNoise) {
  std::vector<float> rir = room_reverb::test::exactEnergyDecay(2 * 48000, 1.0, 0, 13);
  room_reverb::test::addNoiseFloor(rir, -40.0, 14);
  const EnergyDecay decay(rir, 0, kFs);
  ASSERT_TRUE(decay.valid());
  // True curve: -60 dB/s. Uncompensated Schroeder integration with noise would bend the
  // curve upwards from about -30 dB; the compensated one stays on the line.
  for (double t : {0.1, 0.3, 0.5, 0.7}) EXPECT_NEAR(decay.levelDb(t), -60.0 * t, 1.0) << t;
}

TEST(EnergyDecay, PureNoiseHasNoDecay) {
  const std::vector<float> noise = room_reverb::test::whiteNoise(48000, 15);
  const EnergyDecay decay(noise, 0, kFs);
  EXPECT_LT(decay.decayRangeDb(), 15.0);
}

TEST(EnergyDecay, TooShortSignalIsNotAnalysed) {
  const EnergyDecay decay(std::vector<float>(100, 1.0f), 0, kFs);
  EXPECT_FALSE(decay.valid());
  EXPECT_FALSE(decay.lundeby().failure.empty());
}

// From energies per sample, the curve is the one its signal's squares give.
TEST(EnergyDecay, FromEnergiesIsTheCurveOfTheSquares) {
  std::vector<float> rir = room_reverb::test::exponentialDecayNoise(2 * 48000, 0.8, 0, 16);
  room_reverb::test::addNoiseFloor(rir, -50.0, 17);
  std::vector<double> squares(rir.size());
  for (std::size_t n = 0; n < rir.size(); ++n) squares[n] = static_cast<double>(rir[n]) * rir[n];
  for (std::size_t onset : {0u, 480u}) {
    const EnergyDecay from_samples(rir, onset, kFs);
    const EnergyDecay from_energies(squares, onset, kFs);
    ASSERT_TRUE(from_samples.valid() && from_energies.valid());
    EXPECT_EQ(from_energies.lundeby().crosspoint, from_samples.lundeby().crosspoint);
    for (double t : {0.0, 0.2, 0.5}) EXPECT_NEAR(from_energies.levelDb(t), from_samples.levelDb(t), 1e-9) << t;
    EXPECT_NEAR(from_energies.decayTimeS(-5, -25), from_samples.decayTimeS(-5, -25), 1e-9);
  }
  // An onset past the end leaves nothing to analyse.
  EXPECT_FALSE(EnergyDecay(squares, squares.size() + 10, kFs).valid());
}
