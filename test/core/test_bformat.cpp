#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/common/error.h"
#include "synthetic_rir.h"

using namespace room_reverb::core;

namespace {

// A plane wave from (azimuth, elevation) encoded as first-order AmbiX (SN3D):
// W = s, Y = s sin(az) cos(el), Z = s sin(el), X = s cos(az) cos(el).
AudioBuffer ambixPlaneWave(const std::vector<float>& s, double azimuth, double elevation) {
  AudioBuffer b = makeSilentBuffer(4, s.size(), 48000.0);
  for (std::size_t n = 0; n < s.size(); ++n) {
    b.channels[kAcnW][n] = s[n];
    b.channels[kAcnY][n] = static_cast<float>(s[n] * std::sin(azimuth) * std::cos(elevation));
    b.channels[kAcnZ][n] = static_cast<float>(s[n] * std::sin(elevation));
    b.channels[kAcnX][n] = static_cast<float>(s[n] * std::cos(azimuth) * std::cos(elevation));
  }
  return b;
}

}  // namespace

TEST(BFormat, FumaToAmbixReordersAndRescalesW) {
  const std::vector<float> s = room_reverb::test::whiteNoise(64, 1);
  const AudioBuffer ambix = ambixPlaneWave(s, 0.7, 0.3);
  const AudioBuffer fuma = ambixToFuma(ambix);
  // FuMa: W X Y Z with W at -3 dB.
  for (std::size_t n = 0; n < s.size(); ++n) {
    EXPECT_NEAR(fuma.channels[0][n], s[n] / std::sqrt(2.0f), 1e-6);
    EXPECT_FLOAT_EQ(fuma.channels[1][n], ambix.channels[kAcnX][n]);
    EXPECT_FLOAT_EQ(fuma.channels[2][n], ambix.channels[kAcnY][n]);
    EXPECT_FLOAT_EQ(fuma.channels[3][n], ambix.channels[kAcnZ][n]);
  }
  const AudioBuffer back = fumaToAmbix(fuma);
  for (std::size_t c = 0; c < 4; ++c) {
    for (std::size_t n = 0; n < s.size(); ++n) EXPECT_NEAR(back.channels[c][n], ambix.channels[c][n], 1e-6);
  }
}

TEST(BFormat, WrongChannelCountIsAClearError) {
  const AudioBuffer stereo = makeSilentBuffer(2, 10, 48000.0);
  EXPECT_THROW(fumaToAmbix(stereo), InputError);
  EXPECT_THROW(toAmbix(stereo, AmbisonicFormat::kAmbiX), InputError);
}

TEST(BFormat, ParsesFormatNames) {
  EXPECT_EQ(parseAmbisonicFormat("FuMa"), AmbisonicFormat::kFuMa);
  EXPECT_EQ(parseAmbisonicFormat("ambix"), AmbisonicFormat::kAmbiX);
  EXPECT_THROW(parseAmbisonicFormat("n3d"), InputError);
}

TEST(BFormat, DiffuseFieldRatioTellsTheConventions) {
  // A diffuse field: many plane waves from uniformly random directions.
  const std::size_t length = 48000;
  AudioBuffer ambix = makeSilentBuffer(4, length, 48000.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int wave = 0; wave < 400; ++wave) {
    const double azimuth = 2 * M_PI * u(rng);
    const double elevation = std::asin(2 * u(rng) - 1);
    const AudioBuffer w = ambixPlaneWave(room_reverb::test::whiteNoise(length, 100 + wave), azimuth, elevation);
    for (std::size_t c = 0; c < 4; ++c) {
      for (std::size_t n = 0; n < length; ++n) ambix.channels[c][n] += w.channels[c][n];
    }
  }
  EXPECT_NEAR(diffuseDirectionalToOmniRatio(ambix), 1.0, 0.1);
  EXPECT_NEAR(diffuseDirectionalToOmniRatio(ambixToFuma(ambix)), 2.0, 0.2);
  EXPECT_TRUE(checkAmbisonicFormat(ambix, AmbisonicFormat::kAmbiX).empty());
  EXPECT_FALSE(checkAmbisonicFormat(ambix, AmbisonicFormat::kFuMa).empty());
  EXPECT_FALSE(checkAmbisonicFormat(ambixToFuma(ambix), AmbisonicFormat::kAmbiX).empty());
}
