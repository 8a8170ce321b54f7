// room_reverb rsao, run as a user would: a measured B-format file in, the RSAO as a table,
// YAML, VISR JSON and a resynthesised RIR out; every bad input an exit 2 with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "room_reverb/audio/audio_file.h"
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
