// rostest: the binaural_renderer's JACK output. The samples a JACK client hears are the
// samples published on ~binaural, bit for bit; the ports go to the card (the dummy
// backend's playback ports); a server that goes away leaves the stream running on ROS
// time, and one that comes back is joined again.
#include <gtest/gtest.h>

#include <cstdio>
#include <ros/ros.h>
#include <room_reverb/AudioBuffer.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

#include "jack_server.h"
#include "stream_status_watch.h"
#include "tool_run.h"

namespace {

using room_reverb::test::runSiblingNode;
using room_reverb::test::ToolRun;

const std::string kNs = "/jack/binaural_renderer/";
const std::string kServer = "room_reverb_rostest_jack";

// The samples published on ~binaural while `keeping`, and gaps between the chunks' stamps.
struct Topic {
  explicit Topic(ros::NodeHandle& nh) : sub(nh.subscribe(kNs + "binaural", 2000, &Topic::onAudio, this)) {}
  void onAudio(const room_reverb::AudioBuffer::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!keeping) return;
    if (!left.empty() && std::abs((m->header.stamp - last_stamp).toSec() - 512.0 / 48000.0) > 1e-6) ++stamp_gaps;
    last_stamp = m->header.stamp;
    for (std::size_t n = 0; n + 1 < m->samples.size(); n += 2) {
      left.push_back(m->samples[n]);
      right.push_back(m->samples[n + 1]);
    }
  }
  std::mutex mutex;
  bool keeping = false;
  std::vector<float> left, right;
  ros::Time last_stamp;
  int stamp_gaps = 0;
  ros::Subscriber sub;
};

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(JackOutputNode, TheCardHearsWhatTheTopicCarriesAndTheServerMayComeAndGo) {
  ros::NodeHandle nh;
  Topic topic(nh);
  room_reverb::test::StreamStatusWatch status(nh, kNs + "status");
  // The renderer streams by ROS time while there is no server.
  ASSERT_TRUE(status.waitFor([](const room_reverb::StreamStatus& s) {
    return s.chunks_published > 10 && contains(s.jack_output, "waiting for the JACK server");
  }, 30.0)) << status.latest().jack_output;

  auto server = std::make_unique<room_reverb::test::DummyJackServer>(48000.0, 256, kServer);
  ASSERT_TRUE(server->ok());
  ASSERT_TRUE(status.waitFor([](const room_reverb::StreamStatus& s) {
    return contains(s.jack_output, "playing to system:playback_1 and system:playback_2");
  }, 10.0)) << status.latest().jack_output;

  // The recorder leaves before its server does.
  auto recorder_client = std::make_unique<room_reverb::test::JackRecorder>(kServer, "listener", 8 * 48000);
  auto& recorder = *recorder_client;
  ASSERT_TRUE(recorder.ok());
  ASSERT_TRUE(recorder.connectFrom("binaural_renderer:out_left", 0));
  ASSERT_TRUE(recorder.connectFrom("binaural_renderer:out_right", 1));
  // Frames the card asked for and the node's ring did not have (played as silence, the
  // stream kept in step with the card): counted by the node, the one excuse for a
  // difference below.
  const std::uint64_t underrun_before = status.latest().jack_underrun_frames;
  recorder.record();
  {
    std::lock_guard<std::mutex> lock(topic.mutex);
    topic.keeping = true;
  }
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(3.0);
  while (ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.005).sleep();
  }
  ros::WallDuration(0.2).sleep();  // the stream leads the card: let the card catch up
  std::vector<float> topic_left, topic_right;
  {
    std::lock_guard<std::mutex> lock(topic.mutex);
    topic.keeping = false;
    topic_left = topic.left;
    topic_right = topic.right;
    EXPECT_EQ(topic.stamp_gaps, 0);
  }
  const std::vector<float> heard_left = recorder.channel(0), heard_right = recorder.channel(1);
  const int xruns = recorder.xruns();
  recorder_client.reset();
  ASSERT_GT(topic_left.size(), 48000u * 2);
  // The topic's loudest 1024 samples (speech has pauses) must be found in the card's
  // stream. A late cycle or an underrun, which the checks below allow and count, can fall
  // in any one block, so the anchor is the loudest of up to eight blocks apart from each
  // other that the card played whole.
  std::vector<std::pair<double, std::size_t>> blocks;
  for (std::size_t at = 0; at + 1024 <= topic_left.size(); at += 512) {
    double e = 0.0;
    for (std::size_t n = at; n < at + 1024; ++n) e += static_cast<double>(topic_left[n]) * topic_left[n];
    blocks.emplace_back(e, at);
  }
  std::sort(blocks.rbegin(), blocks.rend());
  ASSERT_FALSE(blocks.empty());
  ASSERT_GT(blocks.front().first, 0.0);
  std::size_t loudest = 0;
  long found = -1;
  std::vector<std::size_t> tried;
  for (const auto& [energy, at] : blocks) {
    if (tried.size() == 8 || !(energy > 0.0)) break;
    if (std::any_of(tried.begin(), tried.end(), [&](std::size_t t) { return (at > t ? at - t : t - at) < 1024; })) continue;
    tried.push_back(at);
    found = room_reverb::test::findExact(heard_left, std::vector<float>(topic_left.begin() + static_cast<long>(at),
                                                                         topic_left.begin() + static_cast<long>(at) + 1024));
    if (found >= 0) {
      loudest = at;
      break;
    }
  }
  ASSERT_GE(found, 0) << "the card never played the topic's samples";
  // Align the whole recordings on that and compare every sample both have, period by
  // period. A period that does not match where the last one did is looked for nearby: the
  // server reports a late cycle (an xrun, the machine loaded) and the graph may skip or
  // repeat a period there, which moves the alignment without any frame being wrong.
  constexpr long kPeriod = 256;
  long shift = found - static_cast<long>(loudest);  // card index = topic index + shift
  std::size_t compared = 0, differing = 0;
  int realigned = 0;
  const auto matches = [&](long n, long at_shift) {
    for (long i = n; i < n + kPeriod; ++i) {
      const long k = i + at_shift;
      if (k < 0 || k >= static_cast<long>(heard_left.size())) return false;
      if (heard_left[static_cast<std::size_t>(k)] != topic_left[static_cast<std::size_t>(i)] ||
          heard_right[static_cast<std::size_t>(k)] != topic_right[static_cast<std::size_t>(i)]) {
        return false;
      }
    }
    return true;
  };
  for (long n = 0; n + kPeriod <= static_cast<long>(topic_left.size()); n += kPeriod) {
    if (n + shift < 0 || n + shift + kPeriod > static_cast<long>(heard_left.size())) continue;
    compared += kPeriod;
    if (matches(n, shift)) continue;
    bool moved = false;
    for (long delta = -4 * kPeriod; delta <= 4 * kPeriod && !moved; ++delta) {
      if (delta != 0 && matches(n, shift + delta)) shift += delta, moved = true;
    }
    if (moved) {
      ++realigned;
    } else {
      differing += kPeriod;
    }
  }
  EXPECT_GT(compared, 48000u * 2) << "the recordings overlap for " << compared << " frames";
  // Every realignment needs a late cycle the server reported.
  EXPECT_LE(realigned, xruns) << realigned << " realignments, " << xruns << " xruns";
  // A status from after the recording, with the underruns in it.
  const double recorded_until = ros::Time::now().toSec();
  ASSERT_TRUE(status.waitFor([&](const room_reverb::StreamStatus& s) { return s.header.stamp.toSec() > recorded_until; }, 5.0));
  const std::uint64_t underrun = status.latest().jack_underrun_frames - underrun_before;
  std::printf("[ measured ] %zu of %zu frames differ, %d realignments, %d xruns; the node counted %llu frames of "
              "underrun meanwhile\n", differing, compared, realigned, xruns, static_cast<unsigned long long>(underrun));
  // Every period the card played is the topic's, but for frames the node could not supply
  // in time (a loaded machine delays its thread past a period now and then) and a period
  // at each late cycle; and those are rare: two periods at most in 3 s.
  EXPECT_LE(differing, underrun + static_cast<std::uint64_t>(kPeriod) * static_cast<std::uint64_t>(xruns))
      << "of " << compared << " frames";
  EXPECT_LE(underrun, 2u * 256u);
  const room_reverb::StreamStatus playing = status.latest();
  EXPECT_EQ(playing.jack_overflow_frames, 0u);
  EXPECT_EQ(playing.chunks_dropped, 0u);

  // The server goes: the stream goes on by ROS time and says why.
  server->stop();
  server.reset();
  ASSERT_TRUE(status.waitFor([](const room_reverb::StreamStatus& s) { return contains(s.jack_output, "went away"); }, 10.0))
      << status.latest().jack_output;
  const std::uint64_t published = status.latest().chunks_published;
  EXPECT_TRUE(status.waitFor([&](const room_reverb::StreamStatus& s) { return s.chunks_published > published + 50; }, 5.0));

  // It comes back: the node joins it again.
  server = std::make_unique<room_reverb::test::DummyJackServer>(48000.0, 256, kServer);
  ASSERT_TRUE(server->ok());
  EXPECT_TRUE(status.waitFor([](const room_reverb::StreamStatus& s) { return contains(s.jack_output, "playing to"); }, 10.0))
      << status.latest().jack_output;
}

TEST(JackOutputNode, BadJackParametersStopTheNodeWithOneLine) {
  ros::param::set("/renderer_bad_retry/jack_output", true);
  ros::param::set("/renderer_bad_retry/jack_retry_s", 0.0);
  ToolRun run = runSiblingNode("binaural_renderer", "renderer_bad_retry");
  EXPECT_NE(run.err.find("parameter ~jack_retry_s must be 0.1 to 3600 s"), std::string::npos) << run.err;
  EXPECT_EQ(run.exit_code, 2);

  ros::param::set("/renderer_bad_connect/jack_output", true);
  ros::param::set("/renderer_bad_connect/jack_connect", std::string("system:playback_1"));
  run = runSiblingNode("binaural_renderer", "renderer_bad_connect");
  EXPECT_NE(run.err.find("parameter ~jack_connect: JACK output: connect to \"physical\""), std::string::npos) << run.err;
  EXPECT_EQ(run.exit_code, 2);

  ros::param::set("/renderer_bad_flag/jack_output", std::string("yes"));
  run = runSiblingNode("binaural_renderer", "renderer_bad_flag");
  EXPECT_NE(run.err.find("parameter ~jack_output must be true or false"), std::string::npos) << run.err;
  EXPECT_EQ(run.exit_code, 2);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_jack_output_node");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
