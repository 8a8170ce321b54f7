// rostest: the sample capture bag through replay.launch (the whole graph under the bag's
// clock). A point cloud arrives; the room model answers with the generated room's box
// within the tolerance; the RSAO of the bag's RIR is estimated from the topic and
// through the service; binaural chunks stream at the bag's real-time rate with no dropped
// block; killing rsao_estimator (respawn on) stops nothing else, and it comes back and
// serves again.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <room_reverb/AudioBuffer.h>
#include <room_reverb/BuildRoomModel.h>
#include <room_reverb/EstimateRsao.h>
#include <room_reverb/Rsao.h>
#include <room_reverb/StreamStatus.h>
#include <sensor_msgs/PointCloud2.h>

#include <cmath>
#include <cstdlib>
#include <mutex>
#include <string>

#include "room_reverb/acoustics/room_model.h"

namespace {

using namespace room_reverb;

std::string bagDir() {
  std::string dir;
  ros::NodeHandle("~").getParam("bag_dir", dir);
  return dir;
}

// Everything the graph publishes that the tests look at, with wall-clock arrival times.
struct Listener {
  Listener() {
    ros::NodeHandle nh;
    cloud_sub = nh.subscribe("/rig/points", 1, &Listener::onCloud, this);
    rsao_sub = nh.subscribe("/rig/rsao_estimator/rsao", 1, &Listener::onRsao, this);
    audio_sub = nh.subscribe("/rig/binaural_renderer/binaural", 1000, &Listener::onAudio, this);
    status_sub = nh.subscribe("/rig/binaural_renderer/status", 10, &Listener::onStatus, this);
  }
  void onCloud(const sensor_msgs::PointCloud2ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    cloud_points = static_cast<std::size_t>(m->width) * m->height;
    cloud_frame = m->header.frame_id;
  }
  void onRsao(const room_reverb::RsaoConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    rsao = *m;
    ++rsao_count;
  }
  void onAudio(const room_reverb::AudioBufferConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    // The bag loops: measure the rate within one pass (restart when the clock jumps back).
    if (chunks == 0 || m->header.stamp < last_stamp) {
      first_stamp = m->header.stamp;
      frames = 0;
    }
    last_stamp = m->header.stamp;
    frames += m->samples.size() / std::max<std::uint32_t>(m->channel_count, 1);
    rate = m->sample_rate_hz;
    ++chunks;
  }
  void onStatus(const room_reverb::StreamStatusConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    status = *m;
  }
  template <typename F>
  bool waitFor(F condition, double timeout_s) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (condition()) return true;
      }
      ros::WallDuration(0.05).sleep();
    }
    return false;
  }

  std::mutex mutex;
  ros::Subscriber cloud_sub, rsao_sub, audio_sub, status_sub;
  std::size_t cloud_points = 0;
  std::string cloud_frame;
  room_reverb::Rsao rsao;
  int rsao_count = 0;
  std::size_t chunks = 0, frames = 0;
  double rate = 0.0;
  ros::Time first_stamp, last_stamp;
  room_reverb::StreamStatus status;
};

Listener& listener() {
  static Listener l;
  return l;
}

TEST(Replay, PointCloudArrivesInTheRigFrame) {
  Listener& l = listener();
  ASSERT_TRUE(l.waitFor([&] { return l.cloud_points > 0; }, 120.0)) << "no cloud on /rig/points";
  std::lock_guard<std::mutex> lock(l.mutex);
  EXPECT_EQ(l.cloud_frame, "rig");
  EXPECT_GT(l.cloud_points, 1000000u);  // 2048 x 1024, about 80 % valid
}

TEST(Replay, RoomModelIsTheGeneratedRoom) {
  room_reverb::BuildRoomModel srv;
  ASSERT_TRUE(ros::service::waitForService("/rig/room_model/build", ros::Duration(30.0)));
  // A 2048 x 1024 cloud is some 50 MB: room_model may get it a little after this test node
  // did. Ask again while it says it has none yet.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  do {
    ASSERT_TRUE(ros::service::call("/rig/room_model/build", srv));
    if (srv.response.success || srv.response.message.find("no point cloud") == std::string::npos) break;
    ros::WallDuration(0.5).sleep();
  } while (ros::WallTime::now() < deadline);
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const core::RoomModel truth =
      core::loadRoomModel(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/sample_room/visible.yaml");
  const double got[3] = {srv.response.room.size.x, srv.response.room.size.y, srv.response.room.size.z};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(got[k], truth.size_m[k], std::max(0.03, 0.01 * truth.size_m[k])) << "axis " << k;
  }
  ::testing::Test::RecordProperty("room", srv.response.message);
}

TEST(Replay, RsaoOfTheBagsRirFromTheTopicAndTheService) {
  Listener& l = listener();
  ASSERT_TRUE(l.waitFor([&] { return l.rsao_count > 0; }, 60.0)) << "no RSAO estimated from /rig/impulse_response";
  {
    std::lock_guard<std::mutex> lock(l.mutex);
    EXPECT_GT(l.rsao.reflections.size(), 3u);
  }
  room_reverb::EstimateRsao srv;
  srv.request.file = bagDir() + "/measured_rir.wav";
  srv.request.format = "ambix";
  ASSERT_TRUE(ros::service::call("/rig/rsao_estimator/estimate", srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_GT(srv.response.rsao.reflections.size(), 3u);
}

TEST(Replay, BinauralStreamKeepsTheBagsRealTimeRate) {
  Listener& l = listener();
  // Audio flows once the RSAO arrived; take the stream over the bag's remaining seconds.
  ASSERT_TRUE(l.waitFor([&] { return l.chunks > 20; }, 60.0)) << "no binaural chunks";
  ASSERT_TRUE(l.waitFor([&] { return (l.last_stamp - l.first_stamp).toSec() > 3.0; }, 30.0));
  std::lock_guard<std::mutex> lock(l.mutex);
  const double streamed_s = static_cast<double>(l.frames) / l.rate;
  const double bag_time_s = (l.last_stamp - l.first_stamp).toSec();
  // The chunks cover the bag's time between the first and the last, plus the last chunk.
  EXPECT_NEAR(streamed_s - bag_time_s, 0.0, 0.05) << streamed_s << " s of audio over " << bag_time_s << " s";
  EXPECT_EQ(l.status.chunks_dropped, 0u);
  ::testing::Test::RecordProperty("streamed_s", std::to_string(streamed_s));
  ::testing::Test::RecordProperty("bag_time_s", std::to_string(bag_time_s));
  ::testing::Test::RecordProperty("chunks_late", std::to_string(l.status.chunks_late));
}

TEST(Replay, KilledNodeRespawnsAndTheOthersKeepGoing) {
  Listener& l = listener();
  std::size_t chunks_before = 0;
  {
    std::lock_guard<std::mutex> lock(l.mutex);
    chunks_before = l.chunks;
  }
  ASSERT_EQ(std::system("pkill -f '__name:=rsao_[e]stimator'"), 0) << "rsao_estimator not found to kill";
  ros::WallDuration(1.0).sleep();
  // Back within a few seconds, and serving.
  ASSERT_TRUE(ros::service::waitForService("/rig/rsao_estimator/estimate", ros::Duration(30.0)));
  room_reverb::EstimateRsao srv;
  srv.request.file = bagDir() + "/measured_rir.wav";
  srv.request.format = "ambix";
  bool served = false;
  for (int attempt = 0; attempt < 20 && !served; ++attempt) {
    served = ros::service::call("/rig/rsao_estimator/estimate", srv) && srv.response.success;
    if (!served) ros::WallDuration(0.5).sleep();
  }
  EXPECT_TRUE(served) << srv.response.message;
  std::lock_guard<std::mutex> lock(l.mutex);
  EXPECT_GT(l.chunks, chunks_before) << "the renderer stopped while rsao_estimator was down";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_replay");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  listener();
  return RUN_ALL_TESTS();
}
