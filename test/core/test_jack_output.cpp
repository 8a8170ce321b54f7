// JackOutput against a real JACK server with the dummy backend: the samples written come
// out of the ports bit for bit and in order, the played-frame clock follows the server,
// another server rate is resampled, and bad options, a missing server and a server that
// dies give clear errors and no crash.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <thread>

#include <unistd.h>

#include "jack_server.h"
#include "room_reverb/audio/jack_output.h"
#include "test_files.h"

namespace room_reverb::core {
namespace {

using test::DummyJackServer;
using test::findExact;
using test::JackRecorder;

constexpr double kStreamRate = 48000.0;
// The producer here is a test thread at normal priority on a loaded machine: it writes
// 300 ms ahead (the ring holds 500 ms), so that bit-exactness is tested rather than its
// scheduling. At 100 ms it ran the ring dry when both cores were busy with other work.
constexpr double kTestLead = 14400.0;

// Writes `left` and `right` in chunks of `chunk` frames, each when the output's clock says
// it is due, `lead` frames ahead of what JACK has played: as the renderer paces.
void playPaced(JackOutput& output, const std::vector<float>& left, const std::vector<float>& right, std::size_t chunk,
               double lead) {
  std::vector<float> silence(static_cast<std::size_t>(lead), 0.0f);
  output.write(silence.data(), silence.data(), silence.size());
  for (std::size_t at = 0; at < left.size(); at += chunk) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (output.playedStreamFrames() < static_cast<double>(at) && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    const std::size_t n = std::min(chunk, left.size() - at);
    output.write(left.data() + at, right.data() + at, n);
  }
  // Until the ring has played out, and a period more.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (output.queuedStreamFrames() > 0.0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
}

std::vector<float> noise(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  std::vector<float> x(n);
  for (float& v : x) v = u(rng);
  return x;
}

TEST(JackOutput, PlaysEverySampleInOrderAndConnectsToThePhysicalPorts) {
  DummyJackServer server(kStreamRate, 256);
  ASSERT_TRUE(server.ok());
  JackOutputOptions options;
  options.server_name = server.name();
  options.client_name = "renderer";
  JackOutput output(options);
  EXPECT_EQ(output.serverRateHz(), kStreamRate);
  EXPECT_EQ(output.periodFrames(), 256u);
  // The dummy backend's two playback ports stand for the sound card.
  ASSERT_EQ(output.connectedTo().size(), 2u);
  EXPECT_EQ(output.connectedTo()[0], "system:playback_1");
  EXPECT_EQ(output.connectedTo()[1], "system:playback_2");
  EXPECT_NE(output.description().find("playing to system:playback_1 and system:playback_2"), std::string::npos);

  JackRecorder recorder(server.name(), "listener", 4 * 48000);
  ASSERT_TRUE(recorder.ok());
  ASSERT_TRUE(recorder.connectFrom(output.portName(0), 0));
  ASSERT_TRUE(recorder.connectFrom(output.portName(1), 1));
  const auto connections = recorder.connectionsOf(output.portName(0));
  EXPECT_EQ(connections.size(), 2u);  // the card and the recorder
  recorder.record();

  const std::vector<float> left = noise(48000, 1), right = noise(48000, 2);
  playPaced(output, left, right, 512, kTestLead);
  const std::vector<float> heard_left = recorder.channel(0), heard_right = recorder.channel(1);
  const long start = findExact(heard_left, std::vector<float>(left.begin(), left.begin() + 64));
  ASSERT_GE(start, 0) << "the first samples never came out";
  ASSERT_GE(heard_left.size(), static_cast<std::size_t>(start) + left.size());
  for (std::size_t n = 0; n < left.size(); ++n) {
    ASSERT_EQ(heard_left[static_cast<std::size_t>(start) + n], left[n]) << "left, frame " << n;
    ASSERT_EQ(heard_right[static_cast<std::size_t>(start) + n], right[n]) << "right, frame " << n;
  }
  // Contiguous equality above means the ring never ran dry while the signal played.
  EXPECT_EQ(output.counters().overflow_frames, 0u);
  EXPECT_GE(output.counters().played_frames, left.size());
  EXPECT_TRUE(output.serverRunning());
}

TEST(JackOutput, ClockFollowsTheServer) {
  DummyJackServer server(kStreamRate, 512);
  ASSERT_TRUE(server.ok());
  JackOutputOptions options;
  options.server_name = server.name();
  options.connect = "";
  JackOutput output(options);
  EXPECT_TRUE(output.connectedTo().empty());
  EXPECT_EQ(output.playedStreamFrames(), 0.0);  // the clock starts with the first write
  std::vector<float> one(1, 0.0f);
  output.write(one.data(), one.data(), 1);
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const double played = output.playedStreamFrames();
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // The dummy backend runs on the system clock: the played frames match the time passed
  // within two periods either side.
  EXPECT_NEAR(played, elapsed * kStreamRate, 2 * 512 + 0.02 * kStreamRate);
  EXPECT_EQ(output.queuedStreamFrames(), 0.0);
}

TEST(JackOutput, ResamplesToAServerAtAnotherRate) {
  DummyJackServer server(44100.0, 256, "room_reverb_test_" + std::to_string(::getpid()) + "_44k");
  ASSERT_TRUE(server.ok());
  JackOutputOptions options;
  options.server_name = server.name();
  options.connect = "";
  JackOutput output(options);
  EXPECT_EQ(output.serverRateHz(), 44100.0);
  EXPECT_NE(output.description().find("resampled from 48000 Hz"), std::string::npos);
  JackRecorder recorder(server.name(), "listener", 3 * 44100);
  ASSERT_TRUE(recorder.connectFrom(output.portName(0), 0));
  recorder.record();
  // One second of a 1 kHz sine at 48 kHz comes out as a 1 kHz sine at 44.1 kHz.
  std::vector<float> sine(48000);
  for (std::size_t n = 0; n < sine.size(); ++n) sine[n] = 0.5f * static_cast<float>(std::sin(2.0 * M_PI * 1000.0 * n / kStreamRate));
  playPaced(output, sine, sine, 512, kTestLead);
  const std::vector<float> heard = recorder.channel(0);
  // The first sample above 0.01 starts the tone; half a second in its middle, in ten
  // windows of 50 ms (50 periods of 1 kHz at 44.1 kHz), each correlated with 1 kHz at
  // the server's rate. Windows, not one sum: a client of the dummy server that misses a
  // cycle on a loaded machine is handed a period twice, a phase jump that is the server's
  // and not the stream's; a fault of the resampler or the ring (a wrong rate, a click at
  // every chunk boundary) shows in every window.
  std::size_t onset = 0;
  while (onset < heard.size() && std::abs(heard[onset]) < 0.01f) ++onset;
  constexpr std::size_t kWindow = 2205, kWindows = 10;
  ASSERT_GT(heard.size(), onset + 4410 + kWindows * kWindow);
  std::size_t clean = 0;
  for (std::size_t w = 0; w < kWindows; ++w) {
    double re = 0.0, im = 0.0, energy = 0.0;
    const std::size_t from = onset + 4410 + w * kWindow;
    for (std::size_t n = from; n < from + kWindow; ++n) {
      const double phase = 2.0 * M_PI * 1000.0 * static_cast<double>(n) / 44100.0;
      re += heard[n] * std::cos(phase);
      im += heard[n] * std::sin(phase);
      energy += static_cast<double>(heard[n]) * heard[n];
    }
    const double amplitude = 2.0 * std::hypot(re, im) / static_cast<double>(kWindow);
    // All of the window's energy is in the tone: no clicks.
    const double off_tone = energy / static_cast<double>(kWindow) - amplitude * amplitude / 2.0;
    const bool ok = std::abs(amplitude - 0.5) < 0.005 && std::abs(off_tone) < 1e-4;
    if (!ok) std::cout << "[ window   ] " << w << ": amplitude " << amplitude << ", power off the tone " << off_tone << "\n";
    clean += ok ? 1 : 0;
  }
  EXPECT_GE(clean, kWindows - 1) << "the 1 kHz tone is not clean in " << kWindows - clean << " of " << kWindows << " windows";
  EXPECT_EQ(output.counters().overflow_frames, 0u);
  // The clock counts stream frames: about one second's worth was played.
  EXPECT_GT(output.playedStreamFrames(), 48000.0);
}

TEST(JackOutput, BadOptionsAndAMissingServerGiveOneLine) {
  JackOutputOptions options;
  options.server_name = "room_reverb_no_such_server";
  test::expectInputError([&] { JackOutput output(options); }, {"JACK server \"room_reverb_no_such_server\" is not running"});
  options.client_name = "";
  test::expectInputError([&] { JackOutput output(options); }, {"client name"});
  options.client_name = std::string(200, 'x');
  test::expectInputError([&] { JackOutput output(options); }, {"client name"});
  options.client_name = "renderer";
  options.ring_seconds = 0.0;
  test::expectInputError([&] { JackOutput output(options); }, {"ring"});

  DummyJackServer server(kStreamRate, 256);
  ASSERT_TRUE(server.ok());
  options = JackOutputOptions();
  options.server_name = server.name();
  options.connect = "system:playback_1";
  test::expectInputError([&] { JackOutput output(options); }, {"two ports"});
  for (const std::string bad : {"a,b,c", ",b", "a, ", "   "}) {
    test::expectInputError([&] { parseJackConnect(bad); }, {"two ports \"A,B\"", "(got \"" + bad + "\")"});
  }
  EXPECT_EQ(parseJackConnect(" a , b "), (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(parseJackConnect("physical").empty());
  options.connect = "system:playback_1,nowhere:in";
  test::expectInputError([&] { JackOutput output(options); }, {"no port \"nowhere:in\""});
  options.connect = "system:capture_1,system:playback_2";
  test::expectInputError([&] { JackOutput output(options); }, {"\"system:capture_1\" is not an input port"});
  options.connect = "system:playback_2, system:playback_1";
  JackOutput swapped(options);
  EXPECT_EQ(swapped.connectedTo(), (std::vector<std::string>{"system:playback_2", "system:playback_1"}));
}

TEST(JackOutput, AServerThatDiesIsReportedAndWritesGoOnHarmlessly) {
  DummyJackServer server(kStreamRate, 256);
  ASSERT_TRUE(server.ok());
  JackOutputOptions options;
  options.server_name = server.name();
  JackOutput output(options);
  const std::vector<float> x = noise(4800, 3);
  output.write(x.data(), x.data(), x.size());
  server.stop();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (output.serverRunning() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_FALSE(output.serverRunning());
  EXPECT_FALSE(output.shutdownReason().empty());
  // The ring fills and then counts what it drops; nothing blocks or crashes.
  for (int i = 0; i < 20; ++i) output.write(x.data(), x.data(), x.size());
  EXPECT_GT(output.counters().overflow_frames, 0u);
}

}  // namespace
}  // namespace room_reverb::core
