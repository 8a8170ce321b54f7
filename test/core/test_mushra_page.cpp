// The MUSHRA test page: `mushra make` on a tiny plan (one room, one content, two
// attributes, three conditions: two pages of 1.3 s stimuli) writes the page, test.js and
// one audio script per stimulus that decodes to the stimulus itself; a scripted listener
// (scripts/mushra_listener.py) then completes the test in headless Chromium through the
// page's real controls, opened from the file system and served by `mushra serve`, and the
// CSV the page produced holds exactly the scores it gave, one row per stimulus and page,
// which `mushra analyze` accepts. Chromium is a dependency of the tests (scripts/setup
// installs it): without it these tests fail, they do not skip.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "room_reverb/common/text_file.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/listening/mushra_page.h"
#include "room_reverb/listening/mushra_results.h"
#include "served_tool.h"
#include "synthetic_rir.h"
#include "test_files.h"
#include "tool_run.h"

using namespace room_reverb::core;
using nlohmann::json;
using room_reverb::test::runCommand;
using room_reverb::test::runTool;
using room_reverb::test::ServedTool;
using room_reverb::test::tempPath;
namespace fs = std::filesystem;

namespace {

constexpr double kFs = 48000.0;

// A file the test reads (InputError, and so a failed test, if it is missing).
std::string readAll(const fs::path& path) { return readTextFile(path.string(), "file the test reads"); }

// The plan's inputs: an AmbiX RIR with a clear direct sound and a 0.25 s diffuse tail, a
// second of white noise as the dry content, a small gradient as the panorama.
fs::path writeInputs() {
  const fs::path dir = tempPath("mushra_page_inputs");
  fs::create_directories(dir);
  const std::size_t frames = static_cast<std::size_t>(0.3 * kFs);
  AudioBuffer rir = makeSilentBuffer(4, frames, kFs);
  const double gains[4] = {1.0, 0.5, 0.3, 0.1};  // W, Y, Z, X: a source to the front left
  for (std::size_t c = 0; c < 4; ++c) {
    rir.channels[c][200] = static_cast<float>(gains[c]);
    const std::vector<float> tail = room_reverb::test::exponentialDecayNoise(frames, 0.25, 400, 7 + c);
    for (std::size_t n = 0; n < frames; ++n) rir.channels[c][n] += static_cast<float>(0.03 * tail[n]);
  }
  writeAudioFile((dir / "rir.wav").string(), rir, SampleEncoding::kFloat32);
  AudioBuffer dry = makeSilentBuffer(1, static_cast<std::size_t>(kFs), kFs);
  dry.channels[0] = room_reverb::test::whiteNoise(dry.frameCount(), 3);
  for (float& v : dry.channels[0]) v *= 0.2f;
  writeAudioFile((dir / "dry.wav").string(), dry, SampleEncoding::kFloat32);
  cv::Mat panorama(32, 64, CV_8UC3);
  for (int y = 0; y < panorama.rows; ++y) {
    for (int x = 0; x < panorama.cols; ++x) panorama.at<cv::Vec3b>(y, x) = cv::Vec3b(128, y * 8, x * 4);
  }
  cv::imwrite((dir / "pano.png").string(), panorama);
  std::ofstream(dir / "plan.yaml") << R"(seed: 5
scale: 0-5
rooms:
  - name: tiny
    bformat_rir: rir.wav
    format: ambix
    panorama: pano.png
contents:
  - {name: noise, file: dry.wav}
attributes:
  - {id: spatial_impression, question: "How well does the sound match the room you see?"}
  - {id: overall_quality, question: "How good is the overall sound quality?"}
conditions: [reference, rsao, lowpass_3k5]
hidden_anchors: [reference, lowpass_3k5]
shown_references: [reference]
)";
  return dir / "plan.yaml";
}

struct MadeTest {
  fs::path dir;
  json test;
  int exit_code = -1;
  std::string err;
};

const MadeTest& madeTest() {
  static const MadeTest made = [] {
    MadeTest m;
    m.dir = tempPath("mushra_page_test");
    const auto run = runTool("mushra make --plan " + writeInputs().string() + " --out " + m.dir.string());
    m.exit_code = run.exit_code;
    m.err = run.err;
    if (run.exit_code == 0) m.test = json::parse(readAll(m.dir / "test.json"));
    return m;
  }();
  return made;
}

// RFC 4648 base64 decoding, independent of the encoder under test.
std::string base64Decode(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    const auto value = alphabet.find(c);
    if (value == std::string::npos) return "<invalid character>";
    bits = (bits << 6) | static_cast<std::uint32_t>(value);
    count += 6;
    if (count >= 8) {
      count -= 8;
      out += static_cast<char>((bits >> count) & 0xFF);
    }
  }
  return out;
}

std::uint32_t littleEndian(const std::string& bytes, std::size_t at, int size) {
  std::uint32_t value = 0;
  for (int i = size - 1; i >= 0; --i) value = value << 8 | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

// The browser is part of what the test checks: its absence is a failure, with the fix.
bool chromiumInstalled() { return std::system("command -v chromium >/dev/null 2>&1") == 0; }
const char* kNoChromium =
    "chromium is not installed: the test page is checked in headless Chromium (Debian package chromium; "
    "scripts/setup installs it)";

struct ListenerRun {
  room_reverb::test::ToolRun run;
  fs::path csv;
  json given;
};

// The scripted listener on `target` (the folder or a URL): the reference gets 5 and the
// low anchor 0 everywhere (so the screening keeps the listener), rsao a score per page
// drawn from the seed. `tag` names the output files.
ListenerRun runListener(const std::string& target, const std::string& name, const std::string& tag) {
  ListenerRun l;
  l.csv = tempPath(tag + ".csv");
  const fs::path given = tempPath(tag + "_given.json");
  l.run = runCommand("/usr/bin/python3 " + std::string(ROOM_REVERB_SOURCE_DIR) + "/scripts/mushra_listener.py " +
                     target + " --out " + l.csv.string() + " --given " + given.string() +
                     " --scores reference=5,lowpass_3k5=0 --seed 4 --timeout 30 --name '" + name + "'");
  if (l.run.exit_code == 0) l.given = json::parse(readAll(given));
  return l;
}

// The CSV holds exactly one row per page and stimulus, with the score given to that
// condition on that page, the listener's name, the page's room, content and attribute, a
// letter of the page (each once) and the time spent on the page.
void expectCsvMatchesGiven(const ListenerRun& l, const std::string& name) {
  const MadeTest& m = madeTest();
  const std::vector<MushraRating> rows = parseMushraResultsCsv(readAll(l.csv), l.csv.string(), MushraScale::kZeroToFive);
  std::map<std::pair<std::string, std::string>, double> given;
  for (const json& g : l.given["given"]) given[{g["page"], g["condition"]}] = g["score"];
  std::size_t stimuli = 0;
  for (const json& page : m.test["pages"]) stimuli += page["stimuli"].size();
  EXPECT_EQ(rows.size(), stimuli);
  EXPECT_EQ(given.size(), stimuli);
  std::set<std::pair<std::string, std::string>> seen;
  std::map<std::string, std::set<std::string>> letters;
  for (const MushraRating& r : rows) {
    EXPECT_EQ(r.listener, name);
    EXPECT_TRUE(seen.insert({r.page, r.condition}).second) << r.origin << ": " << r.page << " " << r.condition << " twice";
    const auto found = given.find({r.page, r.condition});
    ASSERT_NE(found, given.end()) << r.origin << ": a row for nothing the listener rated";
    EXPECT_EQ(r.score, found->second) << r.origin;
    EXPECT_EQ(r.page, r.room + "/" + r.content + "/" + r.attribute);
    EXPECT_GT(r.duration_s, 0.0);
    EXPECT_LT(r.duration_s, 60.0);
    letters[r.page].insert(r.letter);
  }
  for (const json& page : m.test["pages"]) {
    EXPECT_EQ(letters[page["id"]], (std::set<std::string>{"A", "B", "C"})) << page["id"];
  }
}

}  // namespace

TEST(MushraPage, Base64AndTheDitheredWavAreExact) {
  EXPECT_EQ(base64Encode(""), "");
  EXPECT_EQ(base64Encode("f"), "Zg==");
  EXPECT_EQ(base64Encode("fo"), "Zm8=");
  EXPECT_EQ(base64Encode("foo"), "Zm9v");
  EXPECT_EQ(base64Encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64Encode(std::string("\xFF\xFE\x00", 3)), "//4A");
  AudioBuffer ramp = makeSilentBuffer(2, 1000, kFs);
  for (std::size_t n = 0; n < 1000; ++n) {
    ramp.channels[0][n] = static_cast<float>(n / 1000.0);
    ramp.channels[1][n] = -2.0f;  // clipped, not wrapped
  }
  const std::string wav = pcm16WavBytes(ramp, 1);
  ASSERT_EQ(wav.size(), 44u + 1000u * 2u * 2u);
  EXPECT_EQ(wav.substr(0, 4), "RIFF");
  EXPECT_EQ(wav.substr(8, 8), "WAVEfmt ");
  EXPECT_EQ(littleEndian(wav, 22, 2), 2u);      // channels
  EXPECT_EQ(littleEndian(wav, 24, 4), 48000u);  // rate
  EXPECT_EQ(littleEndian(wav, 34, 2), 16u);     // bits
  EXPECT_EQ(littleEndian(wav, 40, 4), 4000u);   // data bytes
  for (std::size_t n = 0; n < 1000; n += 37) {
    const auto left = static_cast<std::int16_t>(littleEndian(wav, 44 + 4 * n, 2));
    const auto right = static_cast<std::int16_t>(littleEndian(wav, 46 + 4 * n, 2));
    EXPECT_LE(std::abs(left - n / 1000.0 * 32767.0), 1.5) << n;  // rounding plus dither
    EXPECT_EQ(right, -32768);
  }
  EXPECT_EQ(pcm16WavBytes(ramp, 1), wav);  // the same seed, the same bytes
}

TEST(MushraPage, MakeWritesThePageTheTestScriptAndTheAudioScripts) {
  const MadeTest& m = madeTest();
  ASSERT_EQ(m.exit_code, 0) << m.err;
  ASSERT_EQ(m.test["pages"].size(), 2u);
  // The page as compiled in is the page in the source tree.
  for (const std::string name : {"index.html", "mushra.js", "mushra.css"}) {
    EXPECT_EQ(readAll(m.dir / name), readAll(fs::path(ROOM_REVERB_SOURCE_DIR) / "web" / "mushra" / name)) << name;
  }
  const std::string test_js = readAll(m.dir / "test.js");
  const std::string prefix = "window.MUSHRA_TEST = ";
  ASSERT_EQ(test_js.rfind(prefix, 0), 0u);
  const std::string body = test_js.substr(prefix.size(), test_js.rfind(';') - prefix.size());
  EXPECT_EQ(json::parse(body), m.test);

  for (const json& page : m.test["pages"]) {
    for (const json& s : page["stimuli"]) {
      const std::string file = s["file"], script_file = s["audio_script"];
      const std::string script = readAll(m.dir / script_file);
      const std::string head = "(window.MUSHRA_AUDIO = window.MUSHRA_AUDIO || {})[\"" + file + "\"] =\n\"";
      ASSERT_EQ(script.rfind(head, 0), 0u) << script_file;
      const std::string wav = base64Decode(script.substr(head.size(), script.rfind('"') - head.size()));
      const AudioBuffer stimulus = readAudioFile((m.dir / file).string());
      ASSERT_EQ(wav.size(), 44u + stimulus.frameCount() * 4u) << script_file;
      ASSERT_EQ(wav.substr(0, 4), "RIFF");
      double worst = 0.0;
      for (std::size_t n = 0; n < stimulus.frameCount(); ++n) {
        for (std::size_t c = 0; c < 2; ++c) {
          const auto sample = static_cast<std::int16_t>(littleEndian(wav, 44 + 4 * n + 2 * c, 2));
          worst = std::max(worst, std::abs(sample - stimulus.channels[c][n] * 32767.0));
        }
      }
      EXPECT_LE(worst, 1.5) << script_file << ": the 16-bit copy differs from the stimulus";
    }
  }
}

TEST(MushraPage, AScriptedListenerCompletesTheTestFromTheFileSystem) {
  ASSERT_TRUE(chromiumInstalled()) << kNoChromium;
  const MadeTest& m = madeTest();
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const std::string name = "Ann \"Nym\", listener";
  const ListenerRun l = runListener(m.dir.string(), name, "listener_file");
  ASSERT_EQ(l.run.exit_code, 0) << l.run.err << l.run.out;
  std::cout << l.run.out;
  expectCsvMatchesGiven(l, name);
  // The listener heard something: the page's audio clock ran while it listened.
  EXPECT_NE(l.run.out.find("AudioContext running"), std::string::npos) << l.run.out;

  const fs::path analysis = tempPath("mushra_page_analysis");
  const auto analyze =
      runTool("mushra analyze " + l.csv.string() + " --out " + analysis.string() + " --low-anchors lowpass_3k5");
  ASSERT_EQ(analyze.exit_code, 0) << analyze.err;
  EXPECT_NE(analyze.out.find("kept 1 of 1 listeners"), std::string::npos) << analyze.out;
  const json stats = json::parse(readAll(analysis / "stats.json"));
  EXPECT_FALSE(stats.empty());
}

TEST(MushraPage, ServedTheSamePagePostsItsResultsToTheServer) {
  ASSERT_TRUE(chromiumInstalled()) << kNoChromium;
  const MadeTest& m = madeTest();
  ASSERT_EQ(m.exit_code, 0) << m.err;
  ServedTool server("mushra serve " + m.dir.string() + " --port 0", tempPath("page_serve_err.txt").string());
  const int port = server.port();
  ASSERT_GT(port, 0) << server.firstLine();
  const std::string name = "Bo";
  const ListenerRun l = runListener("http://127.0.0.1:" + std::to_string(port) + "/", name, "listener_http");
  ASSERT_EQ(l.run.exit_code, 0) << l.run.err << l.run.out;
  EXPECT_NE(l.run.out.find("posted to the server"), std::string::npos) << l.run.out;
  expectCsvMatchesGiven(l, name);
  EXPECT_EQ(server.stop(), 0);
  // The server saved what the listener downloaded, byte for byte.
  std::vector<fs::path> saved;
  for (const auto& entry : fs::directory_iterator(m.dir / "results")) saved.push_back(entry.path());
  ASSERT_EQ(saved.size(), 1u);
  EXPECT_EQ(saved.front().filename().string().rfind("Bo_", 0), 0u) << saved.front();
  EXPECT_EQ(readAll(saved.front()), readAll(l.csv));
  EXPECT_NE(server.output().find("saved 6 ratings of Bo"), std::string::npos) << server.output();
}
