// room_reverb mushra make on synthetic rooms with known truth: two B-format RIRs with a
// planted direct sound, reflections and exponential diffuse tail (one AmbiX, one FuMa),
// a tiny room model simulated with few rays, a white-noise and a tone content. Every
// page's stimuli must be equally loud and equally long, the 3.5 kHz anchor must hold
// nothing above 4 kHz, the letters must be a permutation fixed by the seed, and the files
// must say everything a test page needs. And every bad plan is a clear error.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "room_reverb/common/directions.h"
#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/audio/loudness.h"
#include "room_reverb/audio/lowpass_filter.h"
#include "room_reverb/listening/mushra_pages.h"
#include "room_reverb/listening/mushra_plan.h"
#include "room_reverb/listening/mushra_stimuli.h"
#include "synthetic_rir.h"
#include "test_files.h"
#include "tool_run.h"

using namespace room_reverb::core;
using nlohmann::json;
using room_reverb::test::expectInputError;
using room_reverb::test::expectOneLineError;
using room_reverb::test::runTool;
using room_reverb::test::tempPath;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFs = 48000.0;

// A first-order AmbiX RIR: the direct sound from 30 degrees left, three reflections, and a
// diffuse tail (independent noise per channel, X, Y, Z at 1/sqrt(3) of W as in a diffuse
// SN3D field) decaying by 60 dB in t60_s, 28 dB below the direct sound at its start.
AudioBuffer syntheticRir(double t60_s, double length_s, std::uint32_t seed) {
  const std::size_t frames = static_cast<std::size_t>(length_s * kFs);
  AudioBuffer rir = makeSilentBuffer(4, frames, kFs);
  const struct {
    double time_s, amplitude, azimuth_deg, elevation_deg;
  } arrivals[] = {{0.004, 1.0, 30, 0}, {0.009, 0.5, -70, 10}, {0.013, 0.4, 150, -5}, {0.017, 0.3, 90, 40}};
  for (const auto& a : arrivals) {
    const std::vector<double> y = sn3dHarmonics(1, unitVectorFromAngles(a.azimuth_deg * kPi / 180.0, a.elevation_deg * kPi / 180.0));
    const std::size_t n = static_cast<std::size_t>(a.time_s * kFs);
    for (std::size_t c = 0; c < 4; ++c) rir.channels[c][n] += static_cast<float>(a.amplitude * y[c]);
  }
  const std::size_t onset = static_cast<std::size_t>(0.006 * kFs);
  for (std::size_t c = 0; c < 4; ++c) {
    const std::vector<float> noise = room_reverb::test::exponentialDecayNoise(frames, t60_s, onset, seed + c);
    const double level = 0.04 * (c == 0 ? 1.0 : 1.0 / std::sqrt(3.0));
    for (std::size_t n = 0; n < frames; ++n) rir.channels[c][n] += static_cast<float>(level * noise[n]);
  }
  return rir;
}

std::string writeAudio(const fs::path& path, const AudioBuffer& audio) {
  writeAudioFile(path.string(), audio, SampleEncoding::kFloat32);
  return path.string();
}

const char* kRoomModel = R"(frame: room
room_box:
  size_m: [5.0, 4.0, 2.8]
  has_ceiling: true
surfaces:
  floor:      {material: carpet_on_concrete}
  ceiling:    {material: acoustic_ceiling_tiles}
  wall_x_min: {material: brick_painted}
  wall_x_max: {material: plaster_smooth}
  wall_y_min: {material: glass_window}
  wall_y_max: {material: plasterboard_on_studs}
)";

// The plan's text, with the parts the bad-input tests change.
struct PlanParts {
  std::string seed = "11";
  std::string conditions = "[reference, rsao, fast, accurate, wrong_room, lowpass_3k5]";
  std::string anchors = "[reference, wrong_room, lowpass_3k5]";
  std::string shown = "[reference]";
  std::string noise_file = "noise.wav";
  std::string tones_file = "tones.wav";
  std::string second_room = R"(
  - name: hall
    bformat_rir: hall_fuma.wav
    format: fuma
    room: room.yaml
    source_m: [3.5, 2.5, 1.5]
    listener_m: [1.5, 1.5, 1.2]
    panorama: pano.png)";
  std::string small_extra;  // more keys of the first room
  std::string top_extra;    // more top-level keys
};

std::string planText(const PlanParts& p) {
  return "seed: " + p.seed + R"(
scale: 0-5
simulation: {rays: 2000})" +
         p.top_extra + R"(
rooms:
  - name: small
    bformat_rir: small_ambix.wav
    format: ambix
    room: room.yaml
    source_m: [3.6, 2.8, 1.5]
    listener_m: [1.4, 1.2, 1.2]
    panorama: pano.png)" +
         p.small_extra + p.second_room + R"(
contents:
  - {name: noise, file: )" +
         p.noise_file + R"(}
  - {name: tones, file: )" +
         p.tones_file + R"(}
attributes:
  - {id: spatial_impression, question: "How well does the reverberation match the room in the picture?"}
  - {id: overall_quality, question: "How good is the overall sound quality?"}
conditions: )" +
         p.conditions + R"(
hidden_anchors: )" +
         p.anchors + R"(
shown_references: )" +
         p.shown + "\n";
}

// The synthetic inputs, written once per test process.
const fs::path& inputFolder() {
  static const fs::path folder = [] {
    const fs::path dir = tempPath("mushra_inputs");
    fs::create_directories(dir);
    writeAudio(dir / "small_ambix.wav", syntheticRir(0.35, 0.8, 10));
    writeAudio(dir / "hall_fuma.wav", ambixToFuma(syntheticRir(0.9, 1.3, 20)));
    // White noise at 44.1 kHz (resampled by the kit), 2 s.
    AudioBuffer noise = makeSilentBuffer(1, 88200, 44100.0);
    noise.channels[0] = room_reverb::test::whiteNoise(88200, 3);
    for (float& v : noise.channels[0]) v *= 0.1f;
    writeAudio(dir / "noise.wav", noise);
    // A stereo file (mixed to mono by the kit): 500 Hz and 6 kHz tones in turn, 2.4 s.
    AudioBuffer tones = makeSilentBuffer(2, 115200, kFs);
    for (std::size_t n = 0; n < 115200; ++n) {
      const double t = n / kFs;
      const double f = (n / 24000) % 2 == 0 ? 500.0 : 6000.0;
      tones.channels[0][n] = tones.channels[1][n] = static_cast<float>(0.2 * std::sin(2.0 * kPi * f * t));
    }
    writeAudio(dir / "tones.wav", tones);
    writeAudio(dir / "silence.wav", makeSilentBuffer(1, 96000, kFs));
    std::ofstream(dir / "room.yaml") << kRoomModel;
    std::ofstream(dir / "pano.png", std::ios::binary) << "not really a PNG; the kit only copies it";
    std::ofstream(dir / "plan.yaml") << planText({});
    return dir;
  }();
  return folder;
}

fs::path writePlan(const std::string& name, const PlanParts& parts) {
  const fs::path path = inputFolder() / name;
  std::ofstream(path) << planText(parts);
  return path;
}

// One run of the tool on the plan above, shared by the tests that read its output.
struct MadeTest {
  fs::path dir;
  json test;
  double seconds = 0.0;
  int exit_code = -1;
  std::string err;
};

const MadeTest& madeTest() {
  static const MadeTest made = [] {
    MadeTest m;
    m.dir = tempPath("mushra_test_kit");
    const auto start = std::chrono::steady_clock::now();
    const auto run = runTool("mushra make --plan " + (inputFolder() / "plan.yaml").string() + " --out " + m.dir.string());
    m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    m.exit_code = run.exit_code;
    m.err = run.err;
    if (run.exit_code == 0) m.test = json::parse(std::ifstream(m.dir / "test.json"));
    std::cout << "mushra make on the synthetic plan: " << m.seconds << " s\n" << run.out;
    return m;
  }();
  return made;
}

// Fraction of a signal's energy (both ears) above `frequency_hz`, in dB.
double energyAboveDb(const AudioBuffer& audio, double frequency_hz) {
  const std::size_t size = nextFastFftSize(audio.frameCount());
  RealFft fft(size);
  double above = 0.0, total = 0.0;
  for (const auto& channel : audio.channels) {
    std::vector<float> padded(channel);
    padded.resize(size, 0.0f);
    const auto spectrum = fft.forward(padded);
    for (std::size_t k = 0; k < spectrum.size(); ++k) {
      const double power = std::norm(spectrum[k]);
      total += power;
      if (k * audio.sample_rate_hz / size > frequency_hz) above += power;
    }
  }
  return 10.0 * std::log10(above / total);
}

std::vector<std::string> lettersOf(const json& page) {
  std::vector<std::string> letters;
  for (const json& s : page["stimuli"]) letters.push_back(s["letter"]);
  return letters;
}

}  // namespace

// ---- Loudness and the low-pass, on signals with a known answer ----------------------

TEST(Loudness, AStereoSineAtMinus23DbfsReadsMinus23Lufs) {
  // EBU Tech 3341 test case: 1 kHz sine, -23 dBFS peak in both channels -> -23.0 LUFS.
  AudioBuffer sine = makeSilentBuffer(2, 5 * 48000, kFs);
  const double amplitude = std::pow(10.0, -23.0 / 20.0);
  for (std::size_t n = 0; n < sine.frameCount(); ++n) {
    sine.channels[0][n] = sine.channels[1][n] = static_cast<float>(amplitude * std::sin(2.0 * kPi * 1000.0 * n / kFs));
  }
  EXPECT_NEAR(integratedLoudnessLufs(sine, "sine"), -23.0, 0.1);
  EXPECT_NEAR(loudnessMatchingGain(-30.0, -23.0), std::pow(10.0, 7.0 / 20.0), 1e-12);
}

TEST(Loudness, SilenceAndShortSignalsAreErrorsNamingTheSignal) {
  expectInputError([] { integratedLoudnessLufs(makeSilentBuffer(2, 48000, kFs), "stimulus a/b/c"); },
                   {"stimulus a/b/c", "silent"});
  expectInputError([] { integratedLoudnessLufs(makeSilentBuffer(2, 4800, kFs), "short one"); }, {"short one", "0.4 s"});
  expectInputError([] { integratedLoudnessLufs(makeSilentBuffer(4, 48000, kFs), "four"); }, {"four", "4 channels"});
}

TEST(LowpassFilter, PassesBelowStopsAboveAndStaysAligned) {
  const auto sineThrough = [](double f) {
    AudioBuffer s = makeSilentBuffer(1, 48000, kFs);
    for (std::size_t n = 0; n < s.frameCount(); ++n) s.channels[0][n] = static_cast<float>(std::sin(2.0 * kPi * f * n / kFs));
    const AudioBuffer out = lowpassFiltered(s, 3500.0);
    double energy = 0.0;  // the steady middle, away from the ends
    for (std::size_t n = 12000; n < 36000; ++n) energy += out.channels[0][n] * out.channels[0][n];
    return 10.0 * std::log10(energy / 12000.0);  // re a unit sine's mean square 0.5
  };
  EXPECT_NEAR(sineThrough(1000.0), 0.0, 0.01);
  EXPECT_LT(sineThrough(4000.0), -70.0);
  AudioBuffer impulse = makeSilentBuffer(1, 4000, kFs);
  impulse.channels[0][1000] = 1.0f;
  const AudioBuffer out = lowpassFiltered(impulse, 3500.0);
  const auto peak = std::max_element(out.channels[0].begin(), out.channels[0].end());
  EXPECT_EQ(peak - out.channels[0].begin(), 1000);
  EXPECT_EQ(out.frameCount(), 4000u + (kAnchorLowpassTaps - 1) / 2);
}

TEST(CutWithFades, CutsPadsAndRampsBothEnds) {
  AudioBuffer ones = makeSilentBuffer(2, 2000, kFs);
  for (auto& c : ones.channels) std::fill(c.begin(), c.end(), 1.0f);
  const AudioBuffer cut = cutWithFades(ones, 1500);
  ASSERT_EQ(cut.frameCount(), 1500u);
  const std::size_t fade = 480;  // 10 ms
  EXPECT_LT(cut.channels[0][0], 1e-4);
  EXPECT_LT(cut.channels[1][1499], 1e-4);
  EXPECT_NEAR(cut.channels[0][fade / 2], 0.5, 0.01);
  EXPECT_NEAR(cut.channels[0][fade], 1.0, 1e-6);
  EXPECT_NEAR(cut.channels[0][1500 - 1 - fade], 1.0, 1e-6);
  const AudioBuffer padded = cutWithFades(ones, 3000);
  ASSERT_EQ(padded.frameCount(), 3000u);
  EXPECT_EQ(padded.channels[0][2500], 0.0f);
  EXPECT_NEAR(padded.channels[0][1999], 1.0, 1e-6);
}

// ---- The made test ---------------------------------------------------------------------

TEST(MushraMake, RunsOnTheSyntheticPlanInSeconds) {
  const MadeTest& m = madeTest();
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_LT(m.seconds, 30.0);
}

TEST(MushraMake, EveryPageIsEquallyLoudAndEquallyLong) {
  const MadeTest& m = madeTest();
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const double target = m.test["loudness_lufs"];
  EXPECT_NEAR(target, -23.0, 6.0);  // -23 unless a peak forced all lower
  double worst_spread = 0.0;
  for (const json& page : m.test["pages"]) {
    double quietest = 1e9, loudest = -1e9;
    std::set<std::size_t> lengths;
    for (const json& s : page["stimuli"]) {
      const AudioBuffer audio = readAudioFile((m.dir / s["file"].get<std::string>()).string());
      ASSERT_EQ(audio.channelCount(), 2u);
      ASSERT_EQ(audio.sample_rate_hz, 48000.0);
      const double lufs = integratedLoudnessLufs(audio, s["file"]);
      quietest = std::min(quietest, lufs);
      loudest = std::max(loudest, lufs);
      EXPECT_NEAR(lufs, target, 0.05) << s["file"];
      EXPECT_NEAR(lufs, s["loudness_lufs"].get<double>(), 0.01) << s["file"];
      lengths.insert(audio.frameCount());
      float peak = 0.0f;
      for (const auto& c : audio.channels) {
        for (float v : c) peak = std::max(peak, std::abs(v));
      }
      EXPECT_LE(20.0 * std::log10(peak), -1.0 + 1e-4) << s["file"];
    }
    EXPECT_LE(loudest - quietest, 0.5) << page["id"];
    worst_spread = std::max(worst_spread, loudest - quietest);
    EXPECT_EQ(lengths.size(), 1u) << page["id"];
    EXPECT_NEAR(*lengths.begin() / 48000.0, page["duration_s"].get<double>(), 1e-9);
  }
  std::cout << "largest loudness spread on a page: " << worst_spread << " LU\n";
  // The default cut is each content's shortest stimulus: the dry length plus the shortest
  // response (the 0.8 s RIR, whose low-passed anchor is longer), less one sample.
  EXPECT_NEAR(m.test["contents"][0]["duration_s"].get<double>(), 2.0 + 0.8, 0.01);
  EXPECT_NEAR(m.test["contents"][1]["duration_s"].get<double>(), 2.4 + 0.8, 0.01);
}

TEST(MushraMake, TheLowAnchorHoldsNothingAbove4kHz) {
  const MadeTest& m = madeTest();
  ASSERT_EQ(m.exit_code, 0) << m.err;
  for (const std::string room : {"small", "hall"}) {
    for (const std::string content : {"noise", "tones"}) {
      const std::string base = (m.dir / "stimuli" / room / content).string();
      const double anchor = energyAboveDb(readAudioFile(base + "/lowpass_3k5.wav"), 4000.0);
      const double reference = energyAboveDb(readAudioFile(base + "/reference.wav"), 4000.0);
      std::cout << room << "/" << content << ": energy above 4 kHz " << reference << " dB (reference), " << anchor
                << " dB (lowpass_3k5)\n";
      EXPECT_GT(reference, -15.0) << room << "/" << content;  // the reference has plenty there
      EXPECT_LT(anchor, -90.0) << room << "/" << content;
    }
  }
}

TEST(MushraMake, LettersArePermutationsFixedBySeed) {
  const MadeTest& m = madeTest();
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const MushraPlan plan = loadMushraPlan((inputFolder() / "plan.yaml").string());
  const std::vector<MushraPage> pages = mushraPages(plan);
  ASSERT_EQ(pages.size(), m.test["pages"].size());
  std::set<std::vector<std::string>> orders;  // condition order by letter, per page
  for (std::size_t p = 0; p < pages.size(); ++p) {
    const json& page = m.test["pages"][p];
    EXPECT_EQ(lettersOf(page), (std::vector<std::string>{"A", "B", "C", "D", "E", "F"})) << page["id"];
    std::vector<std::string> conditions;
    for (std::size_t i = 0; i < pages[p].stimuli.size(); ++i) {
      EXPECT_EQ(page["stimuli"][i]["condition"], pages[p].stimuli[i].condition);  // what a re-run gives
      conditions.push_back(page["stimuli"][i]["condition"]);
    }
    orders.insert(conditions);
    std::sort(conditions.begin(), conditions.end());
    std::vector<std::string> expected = plan.conditions;
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(conditions, expected) << page["id"];
  }
  EXPECT_GT(orders.size(), pages.size() / 2);  // shuffled per page, not one order for all

  // Same seed, same letters; another seed, other letters.
  const std::vector<MushraPage> again = mushraPages(plan);
  MushraPlan reseeded = plan;
  reseeded.seed = 12;
  const std::vector<MushraPage> other = mushraPages(reseeded);
  bool any_differs = false;
  for (std::size_t p = 0; p < pages.size(); ++p) {
    for (std::size_t i = 0; i < pages[p].stimuli.size(); ++i) {
      EXPECT_EQ(again[p].stimuli[i].condition, pages[p].stimuli[i].condition);
      any_differs |= other[p].stimuli[i].condition != pages[p].stimuli[i].condition;
    }
  }
  EXPECT_TRUE(any_differs);
  // The shuffle itself: a permutation, the same for the same seed and page.
  const std::vector<std::size_t> a = shuffledPositions(26, 5, "x/y/z"), b = shuffledPositions(26, 5, "x/y/z");
  EXPECT_EQ(a, b);
  EXPECT_EQ(std::set<std::size_t>(a.begin(), a.end()).size(), 26u);
  EXPECT_NE(a, shuffledPositions(26, 6, "x/y/z"));
}

TEST(MushraMake, TestJsonSaysEverythingThePageNeeds) {
  const MadeTest& m = madeTest();
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const json& t = m.test;
  EXPECT_EQ(t["seed"], 11);
  EXPECT_EQ(t["scale"]["name"], "0-5");
  EXPECT_EQ(t["scale"]["max"], 5);
  EXPECT_EQ(t["sample_rate_hz"], 48000.0);
  EXPECT_EQ(t["results_columns"].size(), 9u);
  EXPECT_EQ(t["hidden_anchors"], json({"reference", "wrong_room", "lowpass_3k5"}));
  ASSERT_EQ(t["pages"].size(), 2u * 2u * 2u);  // rooms x contents x attributes
  std::set<std::string> ids;
  for (const json& page : t["pages"]) {
    ids.insert(page["id"].get<std::string>());
    EXPECT_FALSE(page["question"].get<std::string>().empty());
    if (page["attribute"] == "spatial_impression") {
      ASSERT_TRUE(page["panorama"].is_string()) << page["id"];
      EXPECT_TRUE(fs::is_regular_file(m.dir / page["panorama"].get<std::string>()));
    } else {
      EXPECT_TRUE(page["panorama"].is_null()) << page["id"];
    }
    ASSERT_EQ(page["stimuli"].size(), 6u);
    for (const json& s : page["stimuli"]) {
      EXPECT_TRUE(fs::is_regular_file(m.dir / s["file"].get<std::string>())) << s["file"];
      const std::string condition = s["condition"];
      EXPECT_EQ(s["is_shown_reference"].get<bool>(), condition == "reference");
      EXPECT_EQ(s["is_hidden_anchor"].get<bool>(),
                condition == "reference" || condition == "wrong_room" || condition == "lowpass_3k5");
      EXPECT_EQ(s["file"], "stimuli/" + page["room"].get<std::string>() + "/" + page["content"].get<std::string>() +
                               "/" + condition + ".wav");
    }
  }
  EXPECT_EQ(ids.size(), 8u);

  // plan_used.yaml reads back as the same plan, with the wrong rooms resolved.
  const MushraPlan used = loadMushraPlan((m.dir / "plan_used.yaml").string());
  EXPECT_EQ(used.seed, 11u);
  EXPECT_EQ(used.conditions.size(), 6u);
  EXPECT_EQ(used.room("small").wrong_room_of, "hall");
  EXPECT_EQ(used.room("hall").wrong_room_of, "small");
  EXPECT_EQ(used.simulation.rays, 2000);

  // webmushra.yaml: one random group of mushra pages, each with its reference and the
  // other five conditions, every path inside the kit once "configs/<DIR name>/" is taken off.
  const YAML::Node config = YAML::LoadFile((m.dir / "webmushra.yaml").string());
  EXPECT_FALSE(config["testname"].as<std::string>().empty());
  const YAML::Node group = config["pages"][0];
  ASSERT_TRUE(group.IsSequence());
  EXPECT_EQ(group[0].as<std::string>(), "random");
  ASSERT_EQ(group.size(), 1u + 8u);
  const std::string prefix = "configs/" + m.dir.filename().string() + "/";
  for (std::size_t i = 1; i < group.size(); ++i) {
    const YAML::Node page = group[i];
    EXPECT_EQ(page["type"].as<std::string>(), "mushra");
    EXPECT_FALSE(page["createAnchor35"].as<bool>());
    EXPECT_FALSE(page["createAnchor70"].as<bool>());
    std::vector<std::string> files = {page["reference"].as<std::string>()};
    EXPECT_NE(files.front().find("/reference.wav"), std::string::npos);
    ASSERT_EQ(page["stimuli"].size(), 5u);
    for (const auto& entry : page["stimuli"]) files.push_back(entry.second.as<std::string>());
    for (const std::string& file : files) {
      ASSERT_EQ(file.rfind(prefix, 0), 0u) << file;
      EXPECT_TRUE(fs::is_regular_file(m.dir / file.substr(prefix.size()))) << file;
    }
  }
  EXPECT_EQ(config["pages"][1]["type"].as<std::string>(), "finish");
}

TEST(MushraStimuli, AGivenDurationAndAPeakLimitKeepEveryStimulusEquallyLoud) {
  // One room, one content; so loud a target that the peaks must bring every stimulus down.
  PlanParts loud;
  loud.second_room = "";
  loud.conditions = "[reference, rsao, lowpass_3k5]";
  loud.anchors = "[reference, lowpass_3k5]";
  loud.top_extra = "\nduration_s: 1.5\nloudness_lufs: -6";
  std::string text = planText(loud);
  text.replace(text.find("  - {name: tones"), std::string("  - {name: tones, file: tones.wav}\n").size(), "");
  const fs::path path = inputFolder() / "loud.yaml";
  std::ofstream(path) << text;
  const MushraPlan plan = loadMushraPlan(path.string());
  const MushraStimuli first = makeMushraStimuli(plan);
  ASSERT_EQ(first.stimuli.size(), 3u);
  EXPECT_LT(first.common_gain_db, 0.0);
  EXPECT_NEAR(first.target_lufs, -6.0 + first.common_gain_db, 1e-9);
  float loudest_peak = -1e9f;
  for (const MushraStimulus& s : first.stimuli) {
    EXPECT_EQ(s.audio.frameCount(), 72000u);  // 1.5 s
    EXPECT_NEAR(s.loudness_lufs, first.target_lufs, 0.01) << s.condition;
    loudest_peak = std::max(loudest_peak, static_cast<float>(s.peak_dbfs));
  }
  EXPECT_NEAR(loudest_peak, -1.0, 1e-3);
  // The same plan again: the same samples, RSAO late noise included.
  const MushraStimuli second = makeMushraStimuli(plan);
  for (std::size_t i = 0; i < first.stimuli.size(); ++i) {
    EXPECT_EQ(first.stimuli[i].audio.channels, second.stimuli[i].audio.channels) << first.stimuli[i].condition;
  }
}

// ---- Bad plans -------------------------------------------------------------------------

TEST(MushraPlan, BadPlansAreClearErrors) {
  const auto expectPlanError = [](const std::string& name, const PlanParts& parts,
                                  const std::vector<std::string>& fragments) {
    const std::string path = writePlan(name, parts).string();
    expectInputError([&] { loadMushraPlan(path); }, fragments);
  };
  PlanParts unknown_condition;
  unknown_condition.conditions = "[reference, rsao, hidden_gem]";
  expectPlanError("unknown_condition.yaml", unknown_condition, {"unknown_condition.yaml", "hidden_gem", "known:"});

  PlanParts unknown_room;
  unknown_room.small_extra = "\n    wrong_room_of: nowhere";
  expectPlanError("unknown_room.yaml", unknown_room, {"wrong_room_of", "unknown room 'nowhere'"});

  PlanParts missing_dry;
  missing_dry.noise_file = "no_such_noise.wav";
  expectPlanError("missing_dry.yaml", missing_dry, {"contents[0] (noise).file", "no_such_noise.wav", "no such file"});

  PlanParts one_room;
  one_room.second_room = "";
  expectPlanError("one_room.yaml", one_room, {"wrong_room", "only one room"});

  PlanParts no_conditions;
  no_conditions.conditions = "[]";
  expectPlanError("no_conditions.yaml", no_conditions, {"conditions", "empty"});

  PlanParts twice;
  twice.conditions = "[reference, rsao, reference]";
  expectPlanError("twice.yaml", twice, {"conditions", "twice"});

  PlanParts shown_not_rated;
  shown_not_rated.conditions = "[rsao, wrong_room]";
  shown_not_rated.anchors = "[wrong_room]";
  shown_not_rated.shown = "[reference]";
  expectPlanError("shown.yaml", shown_not_rated, {"shown_references", "'reference' is not one of the plan's conditions"});

  PlanParts no_seed;
  no_seed.seed = "-3";
  expectPlanError("bad_seed.yaml", no_seed, {"seed", "whole number"});

  // A room without a measured RIR cannot give an RSAO.
  PlanParts no_rir;
  no_rir.second_room = R"(
  - name: model_only
    room: room.yaml
    source_m: [3.5, 2.5, 1.5]
    listener_m: [1.5, 1.5, 1.2]
    panorama: pano.png)";
  expectPlanError("no_rir.yaml", no_rir, {"model_only", "bformat_rir", "missing"});

  const std::string not_yaml = room_reverb::test::writeFile("mushra_not_yaml.yaml", "rooms: [unclosed\n");
  expectInputError([&] { loadMushraPlan(not_yaml); }, {"mushra_not_yaml.yaml"});
  expectInputError([] { loadMushraPlan("/nonexistent/plan.yaml"); }, {"/nonexistent/plan.yaml"});
}

TEST(MushraPlan, ASilentDryFileIsAnErrorBeforeAnyRendering) {
  PlanParts silent;
  silent.tones_file = "silence.wav";
  const MushraPlan plan = loadMushraPlan(writePlan("silent.yaml", silent).string());
  expectInputError([&] { makeMushraStimuli(plan); }, {"content tones", "silence.wav", "silent"});
}

TEST(MushraMake, BadInputExitsTwoWithOneLine) {
  PlanParts unknown_condition;
  unknown_condition.conditions = "[reference, hidden_gem]";
  const std::string out = " --out " + tempPath("mushra_bad_out").string();
  expectOneLineError(runTool("mushra make --plan " + writePlan("tool_unknown.yaml", unknown_condition).string() + out),
                     "hidden_gem");
  PlanParts silent;
  silent.noise_file = "silence.wav";
  expectOneLineError(runTool("mushra make --plan " + writePlan("tool_silent.yaml", silent).string() + out), "silent");
  expectOneLineError(runTool("mushra make --plan /nonexistent/plan.yaml" + out), "/nonexistent/plan.yaml");
  expectOneLineError(runTool("mushra make" + out), "--plan");
  expectOneLineError(runTool("mushra make --plan " + (inputFolder() / "plan.yaml").string()), "--out");
  EXPECT_FALSE(fs::exists(tempPath("mushra_bad_out")));  // nothing written for a bad plan
  // A folder holding something else is not overwritten.
  const fs::path busy = tempPath("mushra_busy_folder");
  fs::create_directories(busy);
  std::ofstream(busy / "thesis.tex") << "precious";
  expectOneLineError(runTool("mushra make --plan " + (inputFolder() / "plan.yaml").string() + " --out " + busy.string()),
                     "not empty");
}
