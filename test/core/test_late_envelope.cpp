// The late envelope's energy over a span of samples (late_envelope.h): the closed form of
// its exponential parts against the sum of the envelope sample by sample.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "room_reverb/rsao/late_envelope.h"

using namespace room_reverb::core;

namespace {

double summedEnergy(const LateReverb& late, std::size_t band, std::size_t from, std::size_t to, double fs) {
  double sum = 0.0;
  for (std::size_t n = from; n < to; ++n) {
    const double e = late.bands[band].level * lateEnvelopeGain(late, band, static_cast<double>(n) / fs);
    sum += e * e;
  }
  return sum;
}

}  // namespace

TEST(LateEnvelope, EnergyInClosedFormEqualsTheSumOverSamples) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double fs = 48000.0;
  for (int trial = 0; trial < 200; ++trial) {
    LateReverb late;
    late.onset_s = 0.002 + 0.02 * unit(random);
    late.mixing_time_s = late.onset_s + 0.005 + 0.1 * unit(random);
    late.course_end_s = trial % 3 == 0 ? 0.0 : late.mixing_time_s + 0.05 * unit(random);
    LateReverbBand band;
    band.level = 0.01 + unit(random);
    band.decay_constant_per_s = 1.0 + 30.0 * unit(random);
    // Both kinds of early course: the paper's ramp (0) and the extension, rising or falling.
    band.onset_level = trial % 2 == 0 ? 0.0 : band.level * std::exp(4.0 * (unit(random) - 0.3));
    // One slope, or a bent decay (rsao.h) in every fifth trial.
    if (trial % 5 == 1) {
      band.first_decay_constant_per_s = band.decay_constant_per_s * (1.2 + 3.0 * unit(random));
      band.second_decay_constant_per_s = band.decay_constant_per_s * (0.2 + 0.7 * unit(random));
      band.second_share = 0.02 + 0.9 * unit(random);
    }
    late.bands.push_back(band);
    // Spans that start before the onset, inside the course, after the join; and end anywhere.
    const auto from = static_cast<std::size_t>(fs * 0.2 * unit(random) * late.mixing_time_s * (trial % 4));
    const auto to = from + static_cast<std::size_t>(fs * 0.3 * unit(random));
    const double expected = summedEnergy(late, 0, from, to, fs);
    const double closed = lateEnvelopeEnergy(late, 0, from, to, fs);
    EXPECT_NEAR(closed, expected, 1e-9 * expected + 1e-300) << "trial " << trial;
  }
  LateReverb silent;
  silent.bands.push_back(LateReverbBand{});
  EXPECT_EQ(lateEnvelopeEnergy(silent, 0, 0, 1000, fs), 0.0);
}

TEST(LateEnvelope, BentDecayStartsAtTheLevelAndEndsOnItsSlowerSlope) {
  LateReverbBand band;
  band.level = 0.5;
  band.decay_constant_per_s = 6.0;
  band.first_decay_constant_per_s = 12.0;
  band.second_decay_constant_per_s = 3.0;
  band.second_share = 0.1;
  EXPECT_DOUBLE_EQ(lateDecayGain(band, 0.0), 1.0);
  // Late on, the slow term alone: sqrt(w) exp(-delta_2 t).
  EXPECT_NEAR(lateDecayGain(band, 2.0) / (std::sqrt(0.1) * std::exp(-3.0 * 2.0)), 1.0, 1e-9);
  // 60 dB down: where the envelope itself is 1e-3, between the two slopes' own T60s.
  const double t = lateDecayLengthS(band);
  EXPECT_NEAR(lateDecayGain(band, t), 1e-3, 1e-9);
  EXPECT_GT(t, 3.0 * std::log(10.0) / 12.0);
  EXPECT_LT(t, 3.0 * std::log(10.0) / 3.0);
  // One slope: the T60.
  band.second_share = 0.0;
  EXPECT_NEAR(lateDecayLengthS(band), 3.0 * std::log(10.0) / 6.0, 1e-12);
  EXPECT_NEAR(lateDecayGain(band, 0.3), std::exp(-6.0 * 0.3), 1e-15);
}
