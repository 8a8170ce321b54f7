#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "room_reverb/common/error.h"
#include "room_reverb/rsao/late_reverb.h"
#include "synthetic_rir.h"

using namespace room_reverb::core;
using room_reverb::test::kFs;

namespace {

const std::vector<double> kT60 = {1.8, 1.6, 1.4, 1.2, 1.0, 0.9, 0.8, 0.6, 0.4};
constexpr std::size_t kOnset = 2400;  // the planted decays start (abruptly) at 50 ms,
constexpr double kMixingS = 0.060;    // the analysis 10 ms later, clear of that start's click
constexpr double kFirstReflectionS = 0.010;

// Each planted band starts at mean square 1/9 (synthetic_rir.h), RMS 1/3, and has decayed
// by 60 dB per T60 until the mixing time.
double trueLevel(std::size_t b) { return std::pow(10.0, -3.0 * (kMixingS - kOnset / kFs) / kT60[b]) / 3.0; }

std::vector<float> plantedDecays(double noise_floor_db, std::uint32_t seed) {
  std::vector<float> rir = room_reverb::test::bandwiseDecayRandomFm(3 * 48000, standardBands(BandResolution::kOctave),
                                                                    kT60, kOnset, seed);
  room_reverb::test::addNoiseFloor(rir, noise_floor_db, seed + 1);
  return rir;
}

// Decay range of band b above white noise at `noise_floor_db` re mean square 1, from the
// mixing time on: the noise's share in the band is its width over the Nyquist band.
double expectedRangeDb(std::size_t b, double noise_floor_db) {
  const FrequencyBand band = standardBands(BandResolution::kOctave)[b];
  const double noise_in_band_db = noise_floor_db + 10.0 * std::log10((band.upper_hz - band.lower_hz) / (kFs / 2));
  return 20.0 * std::log10(trueLevel(b)) - noise_in_band_db;
}

}  // namespace

TEST(LateReverb, RecoversPlantedDecaysAndLevelsInEveryBand) {
  const LateReverb late = estimateLateReverb(plantedDecays(-40.0, 31), kFirstReflectionS, kMixingS);
  EXPECT_DOUBLE_EQ(late.mixing_time_s, kMixingS);
  EXPECT_DOUBLE_EQ(late.onset_s, kFirstReflectionS);
  EXPECT_NEAR(late.attack_time_s, kMixingS - kFirstReflectionS, 1e-12);
  ASSERT_EQ(late.bands.size(), 9u);
  for (std::size_t b = 0; b < 9; ++b) {
    const LateReverbBand& band = late.bands[b];
    ASSERT_GE(expectedRangeDb(b, -40.0), 30.0);  // the premise: every band decays 30 dB clear of the noise
    EXPECT_TRUE(band.reliable) << band.center_hz << ": " << band.reason;
    EXPECT_TRUE(band.reason.empty());
    // Measured: within 0.4 % in every band.
    EXPECT_NEAR(band.t60_s, kT60[b], 0.05 * kT60[b]) << band.center_hz;
    EXPECT_NEAR(band.t60_s, 3.0 * std::log(10.0) / band.decay_constant_per_s, 1e-9);
    // Measured: within 0.05 dB.
    EXPECT_NEAR(20.0 * std::log10(band.level / trueLevel(b)), 0.0, 0.5) << band.center_hz;
  }
  EXPECT_NEAR(late.bands[4].center_hz, 1000.0, 1e-9);
}

TEST(LateReverb, FlagsBandsWithTooLittleRangeAndKeepsTheOthersAccurate) {
  // White noise at -30 dB: the low bands keep 33-50 dB of decay, the top ones under 28 dB.
  const double noise_db = -30.0;
  const LateReverb late = estimateLateReverb(plantedDecays(noise_db, 32), kFirstReflectionS, kMixingS);
  int reliable = 0, flagged = 0;
  for (std::size_t b = 0; b < 9; ++b) {
    const LateReverbBand& band = late.bands[b];
    const double range = expectedRangeDb(b, noise_db);
    if (range >= 32.0) {
      ++reliable;
      EXPECT_TRUE(band.reliable) << band.center_hz << ": " << band.reason;
      EXPECT_NEAR(band.t60_s, kT60[b], 0.05 * kT60[b]) << band.center_hz;
    } else if (range <= 28.0) {
      ++flagged;
      EXPECT_FALSE(band.reliable) << band.center_hz;
      EXPECT_NE(band.reason.find("decay range"), std::string::npos) << band.reason;
    }
  }
  EXPECT_GE(reliable, 5);
  EXPECT_EQ(flagged, 2);  // 8 and 16 kHz
}

TEST(LateReverb, NoiseOnlyBandIsUnreliableNotAFifteenSecondDecay) {
  // Eight planted bands; the 16 kHz band holds nothing but the noise floor.
  std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  bands.pop_back();
  std::vector<double> t60(kT60.begin(), kT60.end() - 1);
  std::vector<float> rir = room_reverb::test::bandwiseDecayRandomFm(3 * 48000, bands, t60, kOnset, 33);
  room_reverb::test::addNoiseFloor(rir, -50.0, 34);
  const LateReverb late = estimateLateReverb(rir, kFirstReflectionS, kMixingS);
  const LateReverbBand& top = late.bands[8];
  EXPECT_FALSE(top.reliable);
  EXPECT_NE(top.reason.find("noise-dominated"), std::string::npos) << top.reason;
  EXPECT_NE(top.reason.find("substituted"), std::string::npos) << top.reason;
  // The substitute is the neighbour's measured decay, not a noise artefact.
  EXPECT_DOUBLE_EQ(top.decay_constant_per_s, late.bands[7].decay_constant_per_s);
  EXPECT_LT(top.t60_s, 1.0);
  // Its level is the noise's RMS in the band: 16 kHz band share of -50 dB white noise.
  const FrequencyBand band16k = standardBands(BandResolution::kOctave)[8];
  const double noise_rms = std::pow(10.0, -50.0 / 20.0) * std::sqrt((band16k.upper_hz - band16k.lower_hz) / (kFs / 2));
  EXPECT_NEAR(20.0 * std::log10(top.level / noise_rms), 0.0, 1.0);
  for (std::size_t b = 0; b < 8; ++b) {
    EXPECT_TRUE(late.bands[b].reliable) << late.bands[b].center_hz << ": " << late.bands[b].reason;
  }
}

TEST(LateReverb, PureNoiseGivesNoMeasuredBandAndTheFallbackDecay) {
  const std::vector<float> noise = room_reverb::test::whiteNoise(48000, 35);
  LateReverbOptions options;
  options.fallback_t60_s = 0.7;
  const LateReverb late = estimateLateReverb(noise, kFirstReflectionS, kMixingS, options);
  for (const LateReverbBand& band : late.bands) {
    EXPECT_FALSE(band.reliable) << band.center_hz;
    EXPECT_NEAR(band.t60_s, 0.7, 1e-9) << band.center_hz;
    EXPECT_NE(band.reason.find("fallback"), std::string::npos) << band.reason;
  }
}

TEST(LateReverb, ClippingInTheTailMakesEveryBandUnreliable) {
  std::vector<float> rir = plantedDecays(-40.0, 36);
  float peak = 0.0f;
  for (float v : rir) peak = std::max(peak, std::abs(v));
  for (std::size_t n = 9000; n < 9004; ++n) rir[n] = peak;  // a flat top at 187 ms
  const LateReverb late = estimateLateReverb(rir, kFirstReflectionS, kMixingS);
  for (const LateReverbBand& band : late.bands) {
    EXPECT_FALSE(band.reliable);
    EXPECT_EQ(band.reason.rfind("clipped input", 0), 0u) << band.reason;
  }
}

TEST(LateReverb, ClippedDirectSoundAloneLeavesTheTailReliable) {
  std::vector<float> rir = plantedDecays(-40.0, 37);
  for (std::size_t n = 100; n < 104; ++n) rir[n] = 4.0f;  // flat-topped direct sound at 2 ms
  const LateReverb late = estimateLateReverb(rir, kFirstReflectionS, kMixingS);
  for (const LateReverbBand& band : late.bands) EXPECT_TRUE(band.reliable) << band.reason;
}

TEST(LateReverb, RejectsBadInput) {
  const std::vector<float> rir = plantedDecays(-40.0, 38);
  EXPECT_THROW(estimateLateReverb({}, 0.0, 0.05), InputError);
  EXPECT_THROW(estimateLateReverb(rir, 0.06, 0.05), InputError);   // mixing before first reflection
  EXPECT_THROW(estimateLateReverb(rir, -0.01, 0.05), InputError);
  EXPECT_THROW(estimateLateReverb(rir, 0.01, 2.95), InputError);   // 50 ms left
  std::vector<float> bad = rir;
  bad[5000] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(estimateLateReverb(bad, 0.01, 0.05), InputError);
}

TEST(LateReverb, DecayOutsideThePlausibleRangeIsFlaggedAndReplaced) {
  LateReverbOptions options;
  options.max_plausible_t60_s = 1.1;  // the three lowest bands (1.2-1.8 s) now count as implausible
  const LateReverb late = estimateLateReverb(plantedDecays(-40.0, 39), kFirstReflectionS, kMixingS, options);
  for (std::size_t b = 0; b < 9; ++b) {
    const LateReverbBand& band = late.bands[b];
    if (kT60[b] > 1.1) {
      EXPECT_FALSE(band.reliable);
      EXPECT_EQ(band.reason.rfind("implausible T60", 0), 0u) << band.reason;
      // Replaced by the nearest measured band's decay (1 kHz: 1.0 s).
      EXPECT_DOUBLE_EQ(band.decay_constant_per_s, late.bands[4].decay_constant_per_s);
    } else {
      EXPECT_TRUE(band.reliable) << band.reason;
    }
  }
}
