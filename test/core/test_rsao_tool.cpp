// room_reverb rsao, run as a user would: a measured B-format file in, the RSAO as a table,
// YAML, VISR JSON and a resynthesised RIR out; every bad input an exit 2 with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "reflection_rooms.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/rsao/rsao_estimator.h"
#include "room_reverb/rsao/rsao_visr_json.h"
#include "room_reverb/rsao/rsao_yaml.h"
#include "room_reverb/common/text_file.h"
#include "test_files.h"
#include "tool_run.h"

using namespace room_reverb::core;
using room_reverb::test::expectOneLineError;
using room_reverb::test::runTool;
using room_reverb::test::tempPath;

namespace {

const std::string kRir = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/rirs/bformat/terrys_typing_room.wav";

std::string writeBuffer(const std::string& name, const AudioBuffer& buffer) {
  const std::string path = tempPath(name).string();
  writeAudioFile(path, buffer, SampleEncoding::kFloat32);
  return path;
}

}  // namespace

TEST(RsaoTool, WritesTheTableYamlVisrJsonAndResynthesis) {
  const std::string yaml = tempPath("terry.yaml").string(), json = tempPath("terry.json").string(),
                    wav = tempPath("terry_resynthesis.wav").string();
  const auto run = runTool("rsao " + kRir + " --format fuma --yaml " + yaml + " --visr-json " + json +
                           " --resynthesis " + wav);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  EXPECT_NE(run.out.find("mixing time"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("16000"), std::string::npos) << run.out;

  const Rsao rsao = loadRsaoYaml(yaml);
  ASSERT_GE(rsao.reflections.size(), 2u);
  ASSERT_EQ(rsao.late.bands.size(), 9u);
  // Terry's typing room: T60 about 2.8 s at 500 Hz.
  EXPECT_NEAR(rsao.late.bands[3].t60_s, 2.78, 0.15);
  // The VISR file holds the same object relative to its direct sound.
  const VisrImport visr = visrJsonToRsao(readTextFile(json, "VISR JSON"));
  ASSERT_EQ(visr.rsao.reflections.size(), rsao.reflections.size());
  EXPECT_NEAR(visr.rsao.reflections[1].time_of_arrival_s,
              rsao.reflections[1].time_of_arrival_s - rsao.reflections[0].time_of_arrival_s, 1e-12);
  const AudioBuffer resynthesis = readAudioFile(wav);
  EXPECT_EQ(resynthesis.channelCount(), 4u);
  EXPECT_EQ(resynthesis.sample_rate_hz, 48000.0);
}

// --paper-onsets selects the paper's group-delay detector, the default matching pursuit;
// each file holds what the library gives with that method.
TEST(RsaoTool, PaperOnsetsSelectTheGroupDelayDetector) {
  const AudioBuffer rir = readAudioFile(kRir);
  for (const bool paper : {false, true}) {
    const std::string yaml = tempPath(paper ? "paper.yaml" : "matched.yaml").string();
    const auto run = runTool("rsao " + kRir + " --format fuma --yaml " + yaml + (paper ? " --paper-onsets" : ""));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    RsaoOptions options;
    options.early.onset_method = paper ? OnsetMethod::kGroupDelay : OnsetMethod::kMatchedPursuit;
    const Rsao expected = estimateRsao(rir, AmbisonicFormat::kFuMa, options);
    const Rsao written = loadRsaoYaml(yaml);
    ASSERT_EQ(written.reflections.size(), expected.reflections.size()) << (paper ? "paper" : "matched");
    for (std::size_t k = 0; k < written.reflections.size(); ++k) {
      EXPECT_NEAR(written.reflections[k].time_of_arrival_s, expected.reflections[k].time_of_arrival_s, 1e-12) << k;
      EXPECT_NEAR(written.reflections[k].azimuth_rad, expected.reflections[k].azimuth_rad, 1e-12) << k;
    }
  }
  expectOneLineError(runTool("rsao " + kRir + " --format fuma --grid"), "--grid goes with --paper-onsets");
  const auto grid = runTool("rsao " + kRir + " --format fuma --paper-onsets --grid");
  EXPECT_EQ(grid.exit_code, 0) << grid.err;
}

// --paper-lpc fits each filter to the window's whole spectrum (lpc_flat_below_hz = 0); by
// default the spectrum below 1/D is held, and the filters differ.
TEST(RsaoTool, PaperLpcFitsTheWholeWindow) {
  const AudioBuffer rir = readAudioFile(kRir);
  std::vector<std::vector<double>> written_lpcs;
  for (const bool paper : {false, true}) {
    const std::string yaml = tempPath(paper ? "paper_lpc.yaml" : "held_lpc.yaml").string();
    const auto run = runTool("rsao " + kRir + " --format fuma --yaml " + yaml + (paper ? " --paper-lpc" : ""));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    RsaoOptions options;
    if (paper) options.early.lpc_flat_below_hz = 0.0;
    const Rsao expected = estimateRsao(rir, AmbisonicFormat::kFuMa, options);
    const Rsao written = loadRsaoYaml(yaml);
    ASSERT_EQ(written.reflections.size(), expected.reflections.size());
    ASSERT_EQ(written.reflections[1].lpc.size(), expected.reflections[1].lpc.size());
    for (std::size_t i = 0; i < expected.reflections[1].lpc.size(); ++i) {
      EXPECT_NEAR(written.reflections[1].lpc[i], expected.reflections[1].lpc[i], 1e-6) << i;
    }
    written_lpcs.push_back(written.reflections[1].lpc);
  }
  double difference = 0.0;
  for (std::size_t i = 0; i < written_lpcs[0].size(); ++i) difference = std::max(difference, std::abs(written_lpcs[0][i] - written_lpcs[1][i]));
  EXPECT_GT(difference, 1e-3);
}

TEST(RsaoTool, ADoubtfulFormatIsAWarningOnStderr) {
  const auto run = runTool("rsao " + kRir + " --format ambix");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.err.find("warning"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("FuMa"), std::string::npos) << run.err;
}

TEST(RsaoTool, BadInput) {
  expectOneLineError(runTool("rsao /nonexistent/rir.wav --format fuma"), "no such file");
  expectOneLineError(runTool("rsao " + kRir), "--format");
  expectOneLineError(runTool("rsao " + kRir + " --format bformat"), "bformat");
  expectOneLineError(runTool("rsao " + kRir + " --format fuma --lpc-order 0"), "lpc_order");
  expectOneLineError(runTool("rsao " + kRir + " --format fuma --window-ms -1"), "analysis_window_s");

  AudioBuffer rir = readAudioFile(kRir);
  AudioBuffer stereo = rir;
  stereo.channels.resize(2);
  expectOneLineError(runTool("rsao " + writeBuffer("stereo.wav", stereo) + " --format fuma"), "got 2");
  const AudioBuffer silent = makeSilentBuffer(4, 48000, 48000.0);
  expectOneLineError(runTool("rsao " + writeBuffer("silent.wav", silent) + " --format fuma"), "silent");
  AudioBuffer short_rir = rir;
  for (auto& c : short_rir.channels) c.resize(2400);
  expectOneLineError(runTool("rsao " + writeBuffer("short.wav", short_rir) + " --format fuma"), "too short");
  // A smooth decaying oscillation: energy from the first sample on, no impulse anywhere.
  AudioBuffer noise = makeSilentBuffer(4, 48000, 48000.0);
  for (std::size_t c = 0; c < 4; ++c) {
    for (std::size_t n = 0; n < noise.frameCount(); ++n) {
      const double t = static_cast<double>(n);
      noise.channels[c][n] = 0.1f * static_cast<float>(std::sin(0.37 * t * static_cast<double>(c + 1)) * std::exp(-t / 9600.0));
    }
  }
  expectOneLineError(runTool("rsao " + writeBuffer("no_direct.wav", noise) + " --format fuma"), "no clear direct sound");
  // Bad input leaves no partial output files behind.
  const std::string yaml = tempPath("never.yaml").string();
  expectOneLineError(runTool("rsao " + writeBuffer("silent2.wav", silent) + " --format fuma --yaml " + yaml), "silent");
  EXPECT_FALSE(std::filesystem::exists(yaml));
}

namespace {

// A synthetic room's RIR and room model as files, its truth at a listener 1.2 m away.
struct MovedCase {
  std::string rir, room;
  Eigen::Vector3d listener;
  room_reverb::test::ReflectionRoom there;
};

MovedCase movedCase() {
  using room_reverb::test::ReflectionRoomSet;
  const auto capture = room_reverb::test::reflectionRoom(ReflectionRoomSet::kDevelopment, 2);
  MovedCase c;
  c.rir = writeBuffer("moved_capture.wav", capture.ambix);
  c.room = tempPath("moved_room.yaml").string();
  saveRoomModel(c.room, room_reverb::test::roomModelOf(capture.geometry));
  // Towards the middle of the room, 1.2 m.
  Eigen::Vector3d inwards = 0.5 * capture.geometry.size_m - capture.geometry.receiver_m;
  inwards.z() = 0.0;
  const Eigen::Vector3d offset = 1.2 * inwards.normalized();
  c.listener = capture.geometry.receiver_m + offset;
  c.there = room_reverb::test::reflectionRoom(ReflectionRoomSet::kDevelopment, 2, offset);
  return c;
}

// The RSAO of an AmbiX file as the tool writes it, without moving.
std::string writeRsao(const std::string& rir) {
  const std::string yaml = tempPath("at_capture.yaml").string();
  const auto run = runTool("rsao " + rir + " --format ambix --yaml " + yaml);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return yaml;
}

std::string point(const Eigen::Vector3d& p) {
  return std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z());
}

TEST(RsaoTool, MovedToAnotherListenerPositionWithTheRoomModel) {
  const MovedCase c = movedCase();
  const std::string yaml = tempPath("moved.yaml").string();
  const auto run = runTool("rsao " + c.rir + " --format ambix --room " + c.room + " --move-to " + point(c.listener) +
                           " --yaml " + yaml);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("matched to the room model"), std::string::npos) << run.out;
  const Rsao moved = loadRsaoYaml(yaml);
  // The direct sound and the first reflection where the truth puts them at the new position.
  const auto& direct = c.there.images.front();
  EXPECT_NEAR(moved.reflections[0].time_of_arrival_s, direct.time_s, 2e-5);
  const Eigen::Vector3d heard(std::cos(moved.reflections[0].elevation_rad) * std::cos(moved.reflections[0].azimuth_rad),
                              std::cos(moved.reflections[0].elevation_rad) * std::sin(moved.reflections[0].azimuth_rad),
                              std::sin(moved.reflections[0].elevation_rad));
  EXPECT_GT(heard.dot(direct.direction), std::cos(2.0 * 3.14159265358979323846 / 180.0));
  EXPECT_NEAR(moved.reflections[0].distance_m, 343.0 * direct.time_s, 0.01);
  // The first-order reflections the estimator finds at the capture point are heard at
  // their true times at the new position; one that it times 0.06 ms off (it overlaps
  // another arrival) may land beyond the 0.1 ms allowed.
  const auto firstOrderFound = [](const room_reverb::test::ReflectionRoom& room, const Rsao& rsao) {
    int found = 0;
    for (const auto& image : room.images) {
      if (image.order != 1) continue;
      for (const EarlyReflection& r : rsao.reflections) found += std::abs(r.time_of_arrival_s - image.time_s) < 1e-4;
    }
    return found;
  };
  const auto capture = room_reverb::test::reflectionRoom(room_reverb::test::ReflectionRoomSet::kDevelopment, 2);
  const int at_capture = firstOrderFound(capture, loadRsaoYaml(writeRsao(c.rir)));
  EXPECT_GE(at_capture, 3);
  EXPECT_GE(firstOrderFound(c.there, moved), at_capture - 1);
}

TEST(RsaoTool, MovedWithoutARoomModelFromTheRigPosition) {
  const MovedCase c = movedCase();
  const std::string rig = point(room_reverb::test::reflectionRoom(room_reverb::test::ReflectionRoomSet::kDevelopment, 2)
                                    .geometry.receiver_m);
  const auto run = runTool("rsao " + c.rir + " --format ambix --rig " + rig + " --move-to " + point(c.listener));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("no room model to check them against"), std::string::npos) << run.out;
}

TEST(RsaoTool, MovingRefusesBadPositionsInOneLine) {
  const MovedCase c = movedCase();
  const std::string base = "rsao " + c.rir + " --format ambix";
  expectOneLineError(runTool(base + " --move-to 1 2"), "--move-to needs three numbers");
  expectOneLineError(runTool(base + " --room " + c.room + " --move-to nan 1 1"), "finite");
  expectOneLineError(runTool(base + " --move-to 1 1 1"), "--rig X Y Z or --room");
  expectOneLineError(runTool(base + " --rig 1 1 1"), "go with --move-to");
  expectOneLineError(runTool(base + " --room " + c.room + " --move-to 1 1 40"), "the listener");
  expectOneLineError(runTool(base + " --room " + c.room + " --rig -3 1 1 --move-to 1 1 1"), "the rig");
  expectOneLineError(runTool(base + " --room /nonexistent/room.yaml --move-to 1 1 1"), "room.yaml");
}

}  // namespace
