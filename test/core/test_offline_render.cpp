// Offline binaural rendering shared by the render tool and ~render_to_file: room response
// conventions, head rotation, order padding, the peak limiter, bad input.
#include <gtest/gtest.h>

#include <cmath>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/binaural/binaural_cues.h"
#include "room_reverb/binaural/offline_render.h"
#include "spherical_head.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;

const BinauralDecoder& decoder3() { return room_reverb::test::sphericalHeadDecoder(3); }

// A plane wave from azimuth `deg` at 2 ms, as AmbiX of `order`.
AudioBuffer planeWave(double deg, int order, double rate = 48000.0) {
  AudioBuffer b = makeSilentBuffer(static_cast<std::size_t>(ambisonicChannelCount(order)), 2048, rate);
  const auto y = sn3dHarmonics(order, {std::cos(deg * kPi / 180.0), std::sin(deg * kPi / 180.0), 0.0});
  for (std::size_t c = 0; c < b.channelCount(); ++c) b.channels[c][static_cast<std::size_t>(0.002 * rate)] = static_cast<float>(y[c]);
  return b;
}

double energy(const std::vector<float>& x) {
  double e = 0.0;
  for (float v : x) e += static_cast<double>(v) * v;
  return e;
}

}  // namespace

TEST(OfflineRender, FumaBecomesAmbixAndOtherRatesAreResampledWithANote) {
  AudioBuffer fuma = makeSilentBuffer(4, 441, 44100.0);
  fuma.channels[0][220] = 1.0f;  // mid-buffer, so the resampled sinc is not cut
  std::vector<std::string> notes;
  const AudioBuffer ambix = ambixRoomResponse(fuma, "fuma", notes);
  EXPECT_EQ(ambix.sample_rate_hz, 48000.0);
  EXPECT_EQ(ambix.frameCount(), 480u);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("44100"), std::string::npos);
  // FuMa's W is SN3D's at -3 dB: the AmbiX W is sqrt(2) times it. An impulse resampled up
  // keeps its DC gain: its samples sum to the rate ratio.
  double sum = 0.0;
  for (float v : ambix.channels[0]) sum += v;
  EXPECT_NEAR(sum, std::sqrt(2.0) * 48000.0 / 44100.0, 0.01);
  EXPECT_EQ(ambixOrder(planeWave(0, 2)), 2);
}

TEST(OfflineRender, TurningTheHeadMovesTheSourceAndLowOrdersArePadded) {
  // A source at 90 degrees left; the head turned 90 degrees left hears it in front.
  const AudioBuffer left = planeWave(90.0, 3);
  const AudioBuffer ahead = planeWave(0.0, 3);
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitZ()));
  const AudioBuffer a = binauralRoomResponse(left, decoder3(), turned);
  const AudioBuffer b = binauralRoomResponse(ahead, decoder3(), Eigen::Quaterniond::Identity());
  ASSERT_EQ(a.channelCount(), 2u);
  for (std::size_t ear = 0; ear < 2; ++ear) {
    for (std::size_t n = 0; n < a.frameCount(); ++n) ASSERT_NEAR(a.channels[ear][n], b.channels[ear][n], 1e-4);
  }
  // Unturned, the left ear is louder.
  const AudioBuffer c = binauralRoomResponse(left, decoder3(), Eigen::Quaterniond::Identity());
  EXPECT_GT(energy(c.channels[0]), 2.0 * energy(c.channels[1]));
  // A first-order room through the third-order decoder: padded, and still left.
  const AudioBuffer d = binauralRoomResponse(planeWave(90.0, 1), decoder3(), Eigen::Quaterniond::Identity());
  EXPECT_GT(energy(d.channels[0]), 1.5 * energy(d.channels[1]));
}

TEST(OfflineRender, ConvolvesAndBringsAPeakAboveFullScaleToMinusOneDbfs) {
  AudioBuffer brir = makeSilentBuffer(2, 3, 48000.0);
  brir.channels[0] = {1.0f, 0.5f, 0.0f};
  brir.channels[1] = {0.0f, 0.0f, 0.25f};
  AudioBuffer source = makeSilentBuffer(1, 2, 48000.0);
  source.channels[0] = {0.5f, 0.5f};
  BinauralRender r = convolveBinaural(source, brir);
  EXPECT_EQ(r.audio.frameCount(), 4u);
  EXPECT_FLOAT_EQ(r.audio.channels[0][1], 0.75f);
  EXPECT_FLOAT_EQ(r.audio.channels[1][3], 0.125f);
  EXPECT_EQ(r.gain_db, 0.0);
  EXPECT_NEAR(r.peak_dbfs, 20.0 * std::log10(0.75), 1e-6);
  source.channels[0] = {4.0f, 4.0f};  // peak 6: brought to -1 dBFS
  r = convolveBinaural(source, brir);
  EXPECT_NEAR(r.peak_dbfs, -1.0, 0.01);
  EXPECT_NEAR(r.gain_db, 20.0 * std::log10(0.891 / 6.0), 0.01);
}

TEST(OfflineRender, BadInput) {
  std::vector<std::string> notes;
  expectInputError([&] { ambixRoomResponse(makeSilentBuffer(3, 10, 48000.0), "fuma", notes); }, {"4 channels", "3"});
  expectInputError([&] { ambixRoomResponse(makeSilentBuffer(5, 10, 48000.0), "ambix", notes); }, {"5 channels"});
  expectInputError([&] { ambixRoomResponse(makeSilentBuffer(2, 10, 48000.0), "mono", notes); }, {"1 channel"});
  expectInputError([&] { ambixRoomResponse(makeSilentBuffer(4, 10, 48000.0), "stereo", notes); }, {"stereo"});
  AudioBuffer nan = makeSilentBuffer(4, 10, 48000.0);
  nan.channels[2][3] = std::nanf("");
  expectInputError([&] { ambixRoomResponse(nan, "ambix", notes); }, {"room response"});
  const BinauralDecoder d1 = makeBinauralDecoder(room_reverb::test::sphericalHeadHrtfSet(), 1);
  expectInputError([&] { binauralRoomResponse(planeWave(0, 3), d1, Eigen::Quaterniond::Identity()); }, {"order-3", "order-1"});
  expectInputError([&] { binauralRoomResponse(planeWave(0, 1, 44100.0), d1, Eigen::Quaterniond::Identity()); }, {"44100"});
  expectInputError([&] { binauralRoomResponse(planeWave(0, 1), d1, Eigen::Quaterniond(2, 0, 0, 0)); }, {"quaternion"});
  expectInputError([&] { convolveBinaural(makeSilentBuffer(2, 4, 48000.0), makeSilentBuffer(2, 4, 48000.0)); }, {"mono"});
  // A corrupt float source: finite, but far beyond full scale, so the render overflows.
  AudioBuffer huge = makeSilentBuffer(1, 64, 48000.0);
  for (float& v : huge.channels[0]) v = 3e38f;
  AudioBuffer brir = makeSilentBuffer(2, 32, 48000.0);
  for (auto& ear : brir.channels) std::fill(ear.begin(), ear.end(), 0.5f);
  expectInputError([&] { convolveBinaural(huge, brir); }, {"overflows", "3e+38", "corrupt"});
}
