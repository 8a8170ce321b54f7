// The `room_reverb metrics` tool, run as a user runs it: good files give the JSON of
// DESIGN.md, bad input gives exit code 2 and one line on stderr.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "test_files.h"
#include "tool_run.h"
#include "room_reverb/audio/audio_file.h"
#include "synthetic_rir.h"

using namespace room_reverb::core;
namespace fs = std::filesystem;

namespace {

using room_reverb::test::expectInputError;
using room_reverb::test::tempPath;
using room_reverb::test::writeFile;

std::string tempPathString(const std::string& name) { return tempPath(name).string(); }

using room_reverb::test::expectOneLineError;
using room_reverb::test::runTool;
using room_reverb::test::ToolRun;

std::string writeRir(const std::string& name, std::vector<float> samples, double rate = 48000.0,
                     SampleEncoding encoding = SampleEncoding::kFloat32) {
  AudioBuffer buffer;
  buffer.sample_rate_hz = rate;
  buffer.channels.push_back(std::move(samples));
  const std::string path = tempPathString(name);
  writeAudioFile(path, buffer, encoding);
  return path;
}

// Patches the float sample at `index` of a float WAV written by writeRir.
void patchFloatSample(const std::string& path, std::size_t frames, std::size_t index, float value) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekp(-static_cast<std::streamoff>((frames - index) * sizeof(float)), std::ios::end);
  file.write(reinterpret_cast<const char*>(&value), sizeof(value));
}

// A 16-bit mono WAV with any sample rate in its header.
void writePcm16Wav(const std::string& path, std::uint32_t rate, const std::vector<float>& samples) {
  std::ofstream out(path, std::ios::binary);
  auto u32 = [&](std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
  auto u16 = [&](std::uint16_t v) { out.write(reinterpret_cast<const char*>(&v), 2); };
  const auto data_bytes = static_cast<std::uint32_t>(samples.size() * 2);
  out.write("RIFF", 4); u32(36 + data_bytes); out.write("WAVE", 4);
  out.write("fmt ", 4); u32(16); u16(1); u16(1); u32(rate); u32(rate * 2); u16(2); u16(16);
  out.write("data", 4); u32(data_bytes);
  for (float v : samples) u16(static_cast<std::uint16_t>(static_cast<std::int16_t>(std::clamp(v, -1.0f, 1.0f) * 32767)));
}

}  // namespace

TEST(MetricsTool, JsonHasTheShapeOfDesignMd) {
  const std::string path = writeRir("decay.wav", room_reverb::test::exponentialDecayNoise(48000, 0.5, 480, 41));
  const ToolRun run = runTool("metrics --json " + path);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["file"], path);
  EXPECT_EQ(j["sample_rate_hz"], 48000);
  EXPECT_EQ(j["channel"], 0);
  ASSERT_EQ(j["bands"].size(), 9u);
  EXPECT_EQ(j["bands"][4]["center_hz"], 1000);
  for (const char* key : {"t20_s", "t30_s", "edt_s", "c50_db", "c80_db", "d50", "ts_s", "drr_db", "reliable", "reason"}) {
    EXPECT_TRUE(j["bands"][4].contains(key)) << key;
    EXPECT_TRUE(j["broadband"].contains(key)) << key;
  }
  EXPECT_NEAR(j["broadband"]["t30_s"].get<double>(), 0.5, 0.01);
  EXPECT_EQ(runTool("metrics --json --bands third " + path).exit_code, 0);
}

TEST(MetricsTool, TableListsEveryBand) {
  const std::string path = writeRir("decay_table.wav", room_reverb::test::exponentialDecayNoise(48000, 0.5, 480, 42));
  const ToolRun run = runTool("metrics " + path);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* label : {"63", "125", "1k", "16k", "broad", "T20 s", "T30 s", "EDT s", "C80 dB", "D50", "DRR dB"}) {
    EXPECT_NE(run.out.find(label), std::string::npos) << label;
  }
}

TEST(MetricsTool, EverySubcommandHasHelp) {
  const ToolRun overview = runTool("--help");
  EXPECT_EQ(overview.exit_code, 0);
  EXPECT_NE(overview.out.find("metrics"), std::string::npos);
  const ToolRun help = runTool("metrics --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("usage: room_reverb metrics"), std::string::npos);
}

TEST(MetricsTool, MissingFile) { expectOneLineError(runTool("metrics /nonexistent/rir.wav"), "no such file"); }

TEST(MetricsTool, FileThatIsNotAudio) {
  const std::string path = tempPathString("notes.wav");
  std::ofstream(path) << "not audio\n";
  expectOneLineError(runTool("metrics " + path), "not a readable audio file");
}

TEST(MetricsTool, EmptyFile) {
  const std::string path = tempPathString("empty.wav");
  std::ofstream(path).close();
  expectOneLineError(runTool("metrics " + path), "empty.wav");
}

TEST(MetricsTool, OneSampleFile) {
  expectOneLineError(runTool("metrics " + writeRir("one.wav", {0.5f})), "at least 10 ms");
}

TEST(MetricsTool, NanAndInfiniteSamples) {
  const std::size_t frames = 4800;
  const std::string nan_path = writeRir("nan.wav", room_reverb::test::exponentialDecayNoise(frames, 0.3, 10, 43));
  patchFloatSample(nan_path, frames, 2000, std::numeric_limits<float>::quiet_NaN());
  expectOneLineError(runTool("metrics " + nan_path), "NaN");
  const std::string inf_path = writeRir("inf.wav", room_reverb::test::exponentialDecayNoise(frames, 0.3, 10, 44));
  patchFloatSample(inf_path, frames, 2000, std::numeric_limits<float>::infinity());
  expectOneLineError(runTool("metrics " + inf_path), "infinite");
}

TEST(MetricsTool, AllZeroRir) {
  expectOneLineError(runTool("metrics " + writeRir("zeros.wav", std::vector<float>(48000, 0.0f))), "silent");
}

TEST(MetricsTool, AbsurdSampleRates) {
  // libsndfile refuses to write such files, so the headers are written by hand.
  for (std::uint32_t rate : {0u, 2000u, 5000000u}) {
    const std::string path = tempPathString("rate_" + std::to_string(rate) + ".wav");
    writePcm16Wav(path, rate, room_reverb::test::exponentialDecayNoise(4800, 0.3, 10, 45));
    const ToolRun run = runTool("metrics " + path);
    EXPECT_EQ(run.exit_code, 2) << rate;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    if (rate != 0) {  // libsndfile itself rejects a 0 Hz header, with its own words
      EXPECT_NE(run.err.find("sample rate"), std::string::npos) << run.err;
    }
  }
}

TEST(MetricsTool, ChannelOutOfRangeAndBadOptions) {
  const std::string path = writeRir("mono.wav", room_reverb::test::exponentialDecayNoise(48000, 0.5, 480, 46));
  expectOneLineError(runTool("metrics --channel 3 " + path), "channel 3 does not exist");
  expectOneLineError(runTool("metrics --bands fifth " + path), "unknown band resolution");
  expectOneLineError(runTool("metrics --frobnicate " + path), "unknown option");
  expectOneLineError(runTool("metrics"), "no impulse-response file");
  expectOneLineError(runTool("nosuchcommand"), "unknown subcommand");
}
