// rostest: the binaural_renderer node streaming in real time. The file-fed renderer must
// publish 10 s of audio at the real-time rate with no dropped chunk and equal the offline
// render of the same looped source in the same room; the topic-fed renderer must take
// rooms from every input, refuse bad ones with a message, and survive bad sources and
// quaternions.
#include <geometry_msgs/QuaternionStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <room_reverb/AudioBuffer.h>
#include <room_reverb/ImpulseResponse.h>
#include <room_reverb/RenderToFile.h>
#include <room_reverb/RoomScene.h>
#include <room_reverb/Rsao.h>
#include <room_reverb/StreamStatus.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <string>

#include "room_scene_message.h"
#include "stream_status_watch.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/audio/channel_mix.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/audio/convolution.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/rsao_conversions.h"
#include "room_reverb/rsao/rsao_estimator.h"
#include "room_reverb/ambisonics/bformat.h"

namespace {

using namespace room_reverb;

const std::string kData = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/";
const std::string kRir = kData + "rirs/bformat/dixon_studio_theatre_r1.wav";
const std::string kSource = kData + "dry/speech.wav";
constexpr double kRate = 48000.0;

// Collects what one renderer publishes.
struct StreamListener {
  explicit StreamListener(ros::NodeHandle& nh, const std::string& ns) : status(nh, ns + "/status") {
    audio_sub = nh.subscribe(ns + "/binaural", 1000, &StreamListener::onAudio, this);
  }
  void onAudio(const room_reverb::AudioBuffer::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    chunks.push_back(*m);
    arrival_wall_s.push_back(ros::WallTime::now().toSec());
  }
  room_reverb::StreamStatus latest() { return status.latest(); }
  bool waitFor(const std::function<bool(const room_reverb::StreamStatus&)>& done, double timeout_s) {
    return status.waitFor(done, timeout_s);
  }
  std::mutex mutex;
  std::vector<room_reverb::AudioBuffer> chunks;
  std::vector<double> arrival_wall_s;
  room_reverb::test::StreamStatusWatch status;
  ros::Subscriber audio_sub;
};

TEST(BinauralRenderer, StreamsTenSecondsInRealTimeEqualToTheOfflineRender) {
  ros::NodeHandle nh;
  StreamListener listener(nh, "/binaural_renderer");
  ASSERT_TRUE(listener.waitFor([](const auto& s) { return s.chunks_published > 0; }, 60.0)) << "no status";
  // 10 s of stream, received.
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(11.0);
  while (ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.002).sleep();
  }
  ASSERT_TRUE(listener.waitFor([](const auto& s) { return s.chunks_published > 0; }, 5.0));
  const room_reverb::StreamStatus status = listener.latest();
  std::vector<room_reverb::AudioBuffer> chunks;
  std::vector<double> arrivals;
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    chunks = listener.chunks;
    arrivals = listener.arrival_wall_s;
  }
  ASSERT_GT(chunks.size(), 100u);
  const std::size_t chunk_frames = status.chunk_frames;
  EXPECT_EQ(chunk_frames, 512u);
  EXPECT_EQ(status.chunks_dropped, 0u);
  EXPECT_EQ(status.clock_restarts, 0u);
  EXPECT_NE(status.room.find("dixon"), std::string::npos) << status.room;

  // Contiguous chunks, each stamped with its first frame's time.
  std::vector<std::int64_t> first_frame;
  for (const auto& c : chunks) {
    ASSERT_EQ(c.channel_count, 2u);
    ASSERT_EQ(c.channel_layout, "binaural");
    ASSERT_EQ(c.samples.size(), 2 * chunk_frames);
    first_frame.push_back(std::llround((c.header.stamp - status.stream_start).toSec() * kRate));
  }
  for (std::size_t k = 1; k < first_frame.size(); ++k) {
    ASSERT_EQ(first_frame[k] - first_frame[k - 1], static_cast<std::int64_t>(chunk_frames)) << "gap at chunk " << k;
  }
  // The real-time rate: stream time received over wall time, and the chunk rate.
  const double stream_s = static_cast<double>(chunks.size() - 1) * chunk_frames / kRate;
  const double wall_s = arrivals.back() - arrivals.front();
  EXPECT_GT(stream_s, 10.0);
  EXPECT_NEAR(stream_s / wall_s, 1.0, 0.03) << "stream " << stream_s << " s in " << wall_s << " s";
  // The audio thread asked for SCHED_FIFO 10 (the default ~realtime_priority); granted or
  // refused, ~status says which.
  EXPECT_TRUE(status.audio_scheduling == "SCHED_FIFO 10" ||
              status.audio_scheduling.rfind("normal (SCHED_FIFO 10 refused", 0) == 0)
      << status.audio_scheduling;
  // Recorded in the test's XML result (rostest keeps no console output of test nodes).
  RecordProperty("audio_scheduling", status.audio_scheduling);
  RecordProperty("chunks", static_cast<int>(chunks.size()));
  RecordProperty("realtime_ratio", std::to_string(stream_s / wall_s));
  RecordProperty("chunks_late", static_cast<int>(status.chunks_late));
  RecordProperty("render_cpu_share", std::to_string(status.render_cpu_share));
  RecordProperty("process_cpu_share", std::to_string(status.process_cpu_share));
  RecordProperty("worst_chunk_render_ms", std::to_string(1000.0 * status.worst_chunk_render_s));
  std::printf("[ measured ] %zu chunks of %zu frames, %.3f s of stream in %.3f s wall (%.1f chunks/s), late %llu, "
              "dropped %llu, renderer CPU %.1f %% of a core, node %.1f %%, worst chunk %.2f ms\n",
              chunks.size(), chunk_frames, stream_s, wall_s, (chunks.size() - 1) / wall_s,
              static_cast<unsigned long long>(status.chunks_late), static_cast<unsigned long long>(status.chunks_dropped),
              100.0 * status.render_cpu_share, 100.0 * status.process_cpu_share, 1000.0 * status.worst_chunk_render_s);

  // The offline render of the looped source (the node loops it from its first sample).
  const std::vector<float> dry = core::toInternalRate(core::mixToMono(core::readAudioFile(kSource))).channels[0];
  const std::int64_t last = first_frame.back() + static_cast<std::int64_t>(chunk_frames);
  std::vector<float> looped(static_cast<std::size_t>(last));
  for (std::size_t n = 0; n < looped.size(); ++n) looped[n] = dry[n % dry.size()];
  std::vector<std::string> notes;
  const core::AudioBuffer room = core::ambixRoomResponse(core::readAudioFile(kRir), "fuma", notes);
  const core::BinauralDecoder decoder = core::makeBinauralDecoder(core::HrtfSet::loadSofa(core::HrtfSet::defaultSofaPath()), 3);
  const core::AudioBuffer brir = core::binauralRoomResponse(room, decoder, Eigen::Quaterniond::Identity());
  double error = 0.0, energy = 0.0;
  for (std::size_t ear = 0; ear < 2; ++ear) {
    const std::vector<float> offline = core::fftConvolve(looped, brir.channels[ear]);
    for (std::size_t k = 0; k < chunks.size(); ++k) {
      for (std::size_t j = 0; j < chunk_frames; ++j) {
        const double want = offline[static_cast<std::size_t>(first_frame[k]) + j];
        const double got = chunks[k].samples[2 * j + ear];
        error += (got - want) * (got - want);
        energy += want * want;
      }
    }
  }
  ASSERT_GT(energy, 0.0);
  const double error_db = 10.0 * std::log10(error / energy + 1e-300);
  std::printf("[ measured ] stream vs offline render: %.1f dB\n", error_db);
  RecordProperty("stream_vs_offline_db", std::to_string(error_db));
  EXPECT_LT(error_db, -100.0);
}

// The topic-fed renderer.
class TopicRenderer : public ::testing::Test {
 protected:
  TopicRenderer() : listener_(nh_, "/topics/binaural_renderer") {
    source_pub_ = nh_.advertise<room_reverb::AudioBuffer>("/topics/binaural_renderer/source", 100);
    ir_pub_ = nh_.advertise<room_reverb::ImpulseResponse>("/topics/binaural_renderer/impulse_response", 1);
    rsao_pub_ = nh_.advertise<room_reverb::Rsao>("/topics/binaural_renderer/rsao", 1);
    scene_pub_ = nh_.advertise<room_reverb::RoomScene>("/topics/binaural_renderer/room_scene", 1);
    head_pub_ = nh_.advertise<geometry_msgs::QuaternionStamped>("/topics/binaural_renderer/head_orientation", 1);
  }
  void SetUp() override {
    ASSERT_TRUE(listener_.waitFor([](const auto& s) { return s.chunks_published > 0; }, 60.0));
    // Let the publishers connect before anything is sent.
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
    while (ros::WallTime::now() < end &&
           (source_pub_.getNumSubscribers() == 0 || ir_pub_.getNumSubscribers() == 0 ||
            rsao_pub_.getNumSubscribers() == 0 || scene_pub_.getNumSubscribers() == 0 ||
            head_pub_.getNumSubscribers() == 0)) {
      ros::WallDuration(0.02).sleep();
    }
  }
  room_reverb::ImpulseResponse impulseResponse(const core::AudioBuffer& audio, const std::string& layout) {
    room_reverb::ImpulseResponse ir;
    ir.audio = ros_bridge::toMessage(audio, layout);
    ir.audio.header.frame_id = "rig";
    return ir;
  }
  // Publishes a room and waits for the status to say it was accepted or refused.
  room_reverb::StreamStatus awaitRoomOutcome(const std::function<void()>& publish) {
    const auto before = listener_.latest();
    publish();
    EXPECT_TRUE(listener_.waitFor(
        [&](const auto& s) { return s.room_changes > before.room_changes || s.rooms_rejected > before.rooms_rejected; },
        30.0));
    return listener_.latest();
  }

  ros::NodeHandle nh_;
  StreamListener listener_;
  ros::Publisher source_pub_, ir_pub_, rsao_pub_, scene_pub_, head_pub_;
};

TEST_F(TopicRenderer, TakesRoomsFromEveryInputAndRefusesBadOnes) {
  const core::AudioBuffer dixon = core::readAudioFile(kRir);
  // An impulse response: accepted; 3 s against max_response_s = 1: truncated, said so.
  auto s = awaitRoomOutcome([&] { ir_pub_.publish(impulseResponse(dixon, "fuma")); });
  EXPECT_NE(s.room.find("impulse_response fuma"), std::string::npos) << s.room;
  EXPECT_NE(s.last_message.find("truncated"), std::string::npos) << s.last_message;
  EXPECT_EQ(s.rooms_rejected, 0u);

  // Three channels: refused with the reason; the room stays.
  core::AudioBuffer three = dixon;
  three.channels.resize(3);
  s = awaitRoomOutcome([&] { ir_pub_.publish(impulseResponse(three, "ambix")); });
  EXPECT_EQ(s.rooms_rejected, 1u);
  EXPECT_NE(s.last_message.find("3 channels"), std::string::npos) << s.last_message;
  EXPECT_NE(s.room.find("impulse_response fuma"), std::string::npos) << s.room;

  // An unknown convention: refused.
  s = awaitRoomOutcome([&] { ir_pub_.publish(impulseResponse(dixon, "stereo")); });
  EXPECT_EQ(s.rooms_rejected, 2u);
  EXPECT_NE(s.last_message.find("stereo"), std::string::npos) << s.last_message;

  // An RSAO (estimated here from the same RIR): resynthesized, accepted.
  const core::Rsao rsao = core::estimateRsao(dixon, core::AmbisonicFormat::kFuMa);
  s = awaitRoomOutcome([&] { rsao_pub_.publish(ros_bridge::toMessage(rsao)); });
  EXPECT_NE(s.room.find("rsao"), std::string::npos) << s.room;

  // A room model through the simulator.
  room_reverb::RoomScene scene = room_reverb::test::shoeboxScene(Eigen::Vector3d(5.0, 4.0, 2.8), Eigen::Vector3d(3.5, 2.0, 1.5),
                                                                 Eigen::Vector3d(1.5, 2.0, 1.5), "fast");
  s = awaitRoomOutcome([&] { scene_pub_.publish(scene); });
  EXPECT_NE(s.room.find("room_scene fast"), std::string::npos) << s.room << " / " << s.last_message;
  EXPECT_NE(s.room.find("order 3"), std::string::npos) << s.room;

  // A room the simulator refuses (the source outside the room): refused, said why.
  scene.source.x = 9.0;
  const auto rejected_before = s.rooms_rejected;
  s = awaitRoomOutcome([&] { scene_pub_.publish(scene); });
  EXPECT_EQ(s.rooms_rejected, rejected_before + 1);
  EXPECT_NE(s.last_message.find("simulator refused"), std::string::npos) << s.last_message;
}

TEST_F(TopicRenderer, SurvivesBadSourcesAndQuaternions) {
  // A 44.1 kHz source with NaN in it: resampled (said), NaN counted, the stream goes on.
  room_reverb::AudioBuffer chunk;
  chunk.sample_rate_hz = 44100.0;
  chunk.channel_count = 1;
  chunk.channel_layout = "mono";
  chunk.samples.assign(4410, 0.1f);
  chunk.samples[100] = std::numeric_limits<float>::quiet_NaN();
  chunk.samples[200] = std::numeric_limits<float>::infinity();
  const auto before = listener_.latest();
  for (int k = 0; k < 5; ++k) source_pub_.publish(chunk);
  EXPECT_TRUE(listener_.waitFor([&](const auto& s) { return s.non_finite_samples >= before.non_finite_samples + 10; },
                                10.0));
  EXPECT_NE(listener_.latest().last_message.find("resampled"), std::string::npos) << listener_.latest().last_message;

  // A malformed chunk (sample count not a multiple of the channels): ignored, said so.
  chunk.channel_count = 3;
  chunk.samples.resize(100);
  source_pub_.publish(chunk);
  EXPECT_TRUE(listener_.waitFor([](const auto& s) { return s.last_message.find("ignored") != std::string::npos; }, 10.0));

  // Malformed quaternions: counted and ignored.
  geometry_msgs::QuaternionStamped q;
  q.quaternion.w = 2.0;
  head_pub_.publish(q);
  q.quaternion.w = std::numeric_limits<double>::quiet_NaN();
  head_pub_.publish(q);
  EXPECT_TRUE(listener_.waitFor([&](const auto& s) { return s.orientations_rejected >= before.orientations_rejected + 2; },
                                10.0));
  // A good one is not counted.
  q.quaternion.w = std::cos(0.25);
  q.quaternion.z = std::sin(0.25);
  head_pub_.publish(q);
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(listener_.latest().orientations_rejected, before.orientations_rejected + 2);
  EXPECT_EQ(listener_.latest().chunks_dropped, 0u);
}

TEST(BinauralRendererService, RendersToFileAndRefusesBadRequests) {
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService("/binaural_renderer/render_to_file", ros::Duration(60.0)));
  ros::ServiceClient client = nh.serviceClient<room_reverb::RenderToFile>("/binaural_renderer/render_to_file");
  const std::string out = "/tmp/room_reverb_test_render_to_file.wav";
  auto call = [&](const std::function<void(room_reverb::RenderToFile::Request&)>& fill) {
    room_reverb::RenderToFile srv;
    srv.request.source_file = kSource;
    srv.request.output_file = out;
    fill(srv.request);
    EXPECT_TRUE(client.call(srv));
    return srv.response;
  };
  std::remove(out.c_str());
  auto r = call([](auto& q) { q.bformat_rir_file = kRir; q.format = "fuma"; });
  ASSERT_TRUE(r.success) << r.message;
  const core::AudioBuffer written = core::readAudioFile(out);
  EXPECT_EQ(written.channelCount(), 2u);
  EXPECT_EQ(written.sample_rate_hz, kRate);
  // Source (2.6 s) plus room (3.0 s) plus the decoder's filters (256 taps at 48 kHz).
  const double source_s = core::toInternalRate(core::readAudioFile(kSource)).durationS();
  EXPECT_NEAR(r.duration_s, source_s + core::readAudioFile(kRir).durationS() + 256.0 / kRate, 0.001);
  EXPECT_LE(r.peak_dbfs, 0.0);

  // The stream's own room, the head turned: also rendered, and different.
  r = call([](auto& q) { q.current_room = true; q.head_orientation.w = std::cos(0.5); q.head_orientation.z = std::sin(0.5); });
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_NE(r.message.find("dixon"), std::string::npos) << r.message;
  const core::AudioBuffer turned = core::readAudioFile(out);
  double difference = 0.0;
  for (std::size_t n = 0; n < std::min(turned.frameCount(), written.frameCount()); ++n) {
    difference = std::max(difference, static_cast<double>(std::abs(turned.channels[0][n] - written.channels[0][n])));
  }
  EXPECT_GT(difference, 1e-3);

  const std::map<std::string, std::function<void(room_reverb::RenderToFile::Request&)>> bad = {
      {"no such file", [](auto& q) { q.source_file = "/nonexistent/dry.wav"; q.bformat_rir_file = kRir; q.format = "fuma"; }},
      {"exactly one room", [](auto&) {}},
      {"exactly one room", [](auto& q) { q.bformat_rir_file = kRir; q.format = "fuma"; q.current_room = true; }},
      {"format", [](auto& q) { q.bformat_rir_file = kRir; }},
      {"malformed quaternion", [](auto& q) { q.current_room = true; q.head_orientation.w = 3.0; }},
      {"output_file", [](auto& q) { q.current_room = true; q.output_file = ""; }},
  };
  for (const auto& [fragment, fill] : bad) {
    r = call(fill);
    EXPECT_FALSE(r.success) << fragment;
    EXPECT_NE(r.message.find(fragment), std::string::npos) << r.message;
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_binaural_renderer");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
