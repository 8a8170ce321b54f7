// The late envelope's energy over a span of samples (late_envelope.h): the closed form of
// its exponential parts against the sum of the envelope sample by sample.
#include <gtest/gtest.h>

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
