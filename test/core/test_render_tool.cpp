// room_reverb render, run as a user would: a dry source through a room response to two
// ears, turned with the head, and every bad input an exit 2 with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/metrics/impulse_response_metrics.h"
#include "synthetic_rir.h"
#include "test_files.h"
#include "tool_run.h"

using namespace room_reverb::core;
using room_reverb::test::expectOneLineError;
using room_reverb::test::runTool;
using room_reverb::test::tempPath;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string writeBuffer(const std::string& name, const AudioBuffer& buffer) {
  const std::string path = tempPath(name).string();
  writeAudioFile(path, buffer, SampleEncoding::kFloat32);
  return path;
}

// An anechoic "room": one first-order plane wave from the left (+y), 10 ms long.
std::string leftPlaneWave() {
  AudioBuffer r = makeSilentBuffer(4, 480, 48000.0);
  const std::vector<double> y = sn3dHarmonics(1, Eigen::Vector3d::UnitY());
  for (std::size_t c = 0; c < 4; ++c) r.channels[c][10] = static_cast<float>(y[c]);
  return writeBuffer("left_plane_wave.wav", r);
}

std::string noiseSource() {
  AudioBuffer s = makeSilentBuffer(1, 24000, 48000.0);
  s.channels[0] = room_reverb::test::whiteNoise(24000, 3);
  for (float& v : s.channels[0]) v *= 0.1f;
  return writeBuffer("noise.wav", s);
}

double ildDb(const std::string& path) {
  const AudioBuffer b = readAudioFile(path);
  double l = 0.0, r = 0.0;
  for (std::size_t n = 0; n < b.frameCount(); ++n) {
    l += b.channels[0][n] * b.channels[0][n];
    r += b.channels[1][n] * b.channels[1][n];
  }
  return 10.0 * std::log10(l / r);
}

}  // namespace

TEST(RenderTool, AMeasuredRoomRendersToTwoEarsAt48k) {
  const std::string out = tempPath("terry_binaural.wav").string();
  const auto run = runTool("render --source " + std::string(ROOM_REVERB_SOURCE_DIR) +
                           "/data/dry/speech.wav --bformat-rir " + ROOM_REVERB_SOURCE_DIR +
                           "/data/rirs/bformat/terrys_typing_room.wav --format fuma --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const AudioBuffer b = readAudioFile(out);
  EXPECT_EQ(b.channelCount(), 2u);
  EXPECT_EQ(b.sample_rate_hz, 48000.0);
  // speech (2.6 s at 44.1 kHz) plus the 5.8 s response
  EXPECT_NEAR(b.durationS(), 2.6 + 5.8, 0.2);
}

TEST(RenderTool, AnRsaoRendersToTwoEars) {
  const std::string rir = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/rirs/bformat/terrys_typing_room.wav";
  const std::string yaml = tempPath("terry_rsao.yaml").string();
  ASSERT_EQ(runTool("rsao " + rir + " --format fuma --yaml " + yaml).exit_code, 0);
  const std::string parametric = tempPath("terry_rsao_binaural.wav").string(),
                    measured = tempPath("terry_measured_binaural.wav").string();
  // An impulse as the source: each render is then the room's binaural response.
  AudioBuffer impulse = makeSilentBuffer(1, 480, 48000.0);
  impulse.channels[0][0] = 1.0f;
  const std::string source = writeBuffer("impulse.wav", impulse);
  const auto run = runTool("render --source " + source + " --rsao " + yaml + " --out " + parametric);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ASSERT_EQ(runTool("render --source " + source + " --bformat-rir " + rir + " --format fuma --out " + measured).exit_code, 0);
  // The parametric route decays as the measured reference at each ear (500 Hz - 4 kHz,
  // where the RSAO's T20 is within 10 % of the measured one: test_rsao_estimator).
  const AudioBuffer a = readAudioFile(parametric), b = readAudioFile(measured);
  ASSERT_EQ(a.channelCount(), 2u);
  for (int ear = 0; ear < 2; ++ear) {
    const MetricsReport pa = analyseImpulseResponse(a, ear), pb = analyseImpulseResponse(b, ear);
    for (std::size_t band = 3; band <= 6; ++band) {
      ASSERT_TRUE(pa.bands[band].t20_s && pb.bands[band].t20_s);
      EXPECT_NEAR(*pa.bands[band].t20_s / *pb.bands[band].t20_s, 1.0, 0.10)
          << "ear " << ear << ", " << pa.bands[band].nominal_hz << " Hz";
    }
  }
}

TEST(RenderTool, TheHeadTurnedTowardsTheSourceHearsItInFront) {
  const std::string facing = tempPath("facing.wav").string(), turned = tempPath("turned.wav").string();
  const std::string common = "render --source " + noiseSource() + " --ambisonic-rir " + leftPlaneWave();
  ASSERT_EQ(runTool(common + " --out " + facing).exit_code, 0);
  ASSERT_EQ(runTool(common + " --yaw 90 --out " + turned).exit_code, 0);
  EXPECT_GT(ildDb(facing), 4.0);
  EXPECT_NEAR(ildDb(turned), 0.0, 1.0);
}

TEST(RenderTool, BadInput) {
  const std::string out = tempPath("never.wav").string();
  const std::string source = noiseSource(), room = leftPlaneWave();
  expectOneLineError(runTool("render --source /nonexistent/dry.wav --ambisonic-rir " + room + " --out " + out), "no such file");
  expectOneLineError(runTool("render --source " + source + " --out " + out), "exactly one");
  expectOneLineError(runTool("render --source " + source + " --bformat-rir " + room + " --out " + out), "--format");
  expectOneLineError(runTool("render --source " + source + " --ambisonic-rir " + room + " --hrtf /nonexistent.sofa --out " + out),
                     "nonexistent.sofa");
  const std::string garbage = room_reverb::test::writeFile("garbage.sofa", "not an HDF5 file at all");
  expectOneLineError(runTool("render --source " + source + " --ambisonic-rir " + room + " --hrtf " + garbage + " --out " + out),
                     "garbage.sofa");
  AudioBuffer three = makeSilentBuffer(3, 480, 48000.0);
  three.channels[0][0] = 1.0f;
  expectOneLineError(runTool("render --source " + source + " --ambisonic-rir " + writeBuffer("three.wav", three) + " --out " + out),
                     "3 channels");
  expectOneLineError(runTool("render --source " + source + " --ambisonic-rir " + room + " --decoder best --out " + out), "best");
  expectOneLineError(runTool("render --source " + source + " --rsao /nonexistent/rsao.yaml --out " + out), "no such file");
  expectOneLineError(runTool("render --source " + source + " --rsao x.yaml --ambisonic-rir " + room + " --out " + out),
                     "exactly one");
  EXPECT_FALSE(std::filesystem::exists(out));
}
