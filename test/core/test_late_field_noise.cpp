// The late field's noise: each band normalised to unit energy where it has any, the same
// to the bit whether it is made afresh or taken from the cache, and a synthesis at one
// seed repeated gives the same response.
#include <gtest/gtest.h>

#include <cmath>

#include "room_reverb/acoustics/impulse_response_synthesis.h"
#include "room_reverb/acoustics/late_field_noise.h"

namespace room_reverb::core {
namespace {

constexpr double kFs = 48000.0;

BandFilterBank octaveBank() { return BandFilterBank(standardBands(BandResolution::kOctave), kFs, 0.5, Complementarity::kAmplitude); }

LateFieldNoiseShape shapeOf(std::uint32_t seed) {
  LateFieldNoiseShape shape;
  shape.seed = seed;
  shape.frames = static_cast<std::size_t>(0.5 * kFs);
  shape.channels = 2;
  shape.sample_rate_hz = kFs;
  shape.room_volume_m3 = 60.0;
  shape.bin_frames = 48.0;
  return shape;
}

TEST(LateFieldNoise, EachBandHasUnitEnergyOnceTheEventsAreDense) {
  const BandFilterBank bank = octaveBank();
  std::vector<bool> wanted(bank.bands().size(), false);
  wanted[3] = wanted[6] = true;  // 250 Hz and 2 kHz
  const auto noise = lateFieldNoise(shapeOf(11), bank, wanted);
  EXPECT_TRUE(noise->normalised[0].empty());
  for (std::size_t t : {3u, 6u}) {
    ASSERT_EQ(noise->normalised[t].size(), 2u);
    for (const std::vector<float>& channel : noise->normalised[t]) {
      ASSERT_EQ(channel.size(), static_cast<std::size_t>(0.5 * kFs));
      // From 0.1 s the reflection density (4 pi c^3 t^2 / V) is at its cap of 12 000/s.
      double sum = 0.0;
      for (std::size_t n = 4800; n < channel.size() - 4800; ++n) sum += static_cast<double>(channel[n]) * channel[n];
      EXPECT_NEAR(sum / static_cast<double>(channel.size() - 9600), 1.0, 0.1) << "band " << t;
    }
  }
  EXPECT_EQ(noise->bytes(), 2u * 2u * static_cast<std::size_t>(0.5 * kFs) * sizeof(float));
}

TEST(LateFieldNoise, CachedNoiseIsTheFreshOneAndOtherSeedsDiffer) {
  const BandFilterBank bank = octaveBank();
  std::vector<bool> one(bank.bands().size(), false), two(bank.bands().size(), false);
  one[5] = true;
  two[5] = two[7] = true;  // another set of bands: made afresh, not taken from the cache
  const auto first = lateFieldNoise(shapeOf(21), bank, one);
  const auto again = lateFieldNoise(shapeOf(21), bank, one);
  EXPECT_EQ(first.get(), again.get());
  const auto fresh = lateFieldNoise(shapeOf(21), bank, two);
  EXPECT_NE(first.get(), fresh.get());
  EXPECT_EQ(first->normalised[5], fresh->normalised[5]);
  const auto other = lateFieldNoise(shapeOf(22), bank, one);
  EXPECT_NE(first->normalised[5], other->normalised[5]);
  LateFieldNoiseShape louder_room = shapeOf(21);
  louder_room.room_volume_m3 = 600.0;  // a sparser start: another sequence
  EXPECT_NE(lateFieldNoise(louder_room, bank, one)->normalised[5], first->normalised[5]);
}

TEST(LateFieldNoise, ASynthesisRepeatedAtOneSeedIsTheSame) {
  EnergyHistogram late(0.001, 800);
  for (int bin = 20; bin < 800; ++bin) {
    for (int b = 0; b < kOctaveBandCount; ++b) late.add((bin + 0.5) * 0.001, b, 1e-4 * std::exp(-bin * 0.01), Eigen::Vector3d::UnitY());
  }
  SynthesisOptions options;
  options.duration_s = 0.8;
  options.ambisonic_order = 1;
  options.seed = 31;
  const AudioBuffer first = synthesizeImpulseResponse({}, &late, options);
  const AudioBuffer second = synthesizeImpulseResponse({}, &late, options);
  ASSERT_EQ(first.channelCount(), 4u);
  for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(first.channels[c], second.channels[c]) << "channel " << c;
  options.seed = 32;
  EXPECT_NE(synthesizeImpulseResponse({}, &late, options).channels[0], first.channels[0]);
}

}  // namespace
}  // namespace room_reverb::core
