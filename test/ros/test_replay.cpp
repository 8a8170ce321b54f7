// rostest: the sample capture bag through replay.launch (the whole graph under the bag's
// clock). A point cloud arrives; the room model answers with the generated room's box
// within the tolerance; the RSAO of the bag's RIR is estimated from the topic and
// through the service; binaural chunks stream at the bag's real-time rate with no dropped
// block. Then every node of the graph is killed in turn (SIGKILL, respawn on): each comes
// back as a new process that advertises its topics and services again and re-publishes
// its latched state, no other node dies, and the binaural stream keeps flowing (or, for
// the renderer itself, resumes).
#include <gtest/gtest.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <room_reverb/AudioBuffer.h>
#include <room_reverb/BuildRoomModel.h>
#include <room_reverb/EstimateRsao.h>
#include <room_reverb/RoomModel.h>
#include <room_reverb/Rsao.h>
#include <room_reverb/SimulateRoom.h>
#include <room_reverb/StreamStatus.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <signal.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

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
    const std::size_t chunk_frames = m->samples.size() / std::max<std::uint32_t>(m->channel_count, 1);
    frames += chunk_frames;
    rate = m->sample_rate_hz;
    ++chunks;
    const ros::WallTime now = ros::WallTime::now();
    window_max_gap_s = std::max(window_max_gap_s, (now - gap_from).toSec());
    gap_from = now;
    // The bag's time the window's chunks span: from one chunk's stamp to the next (a
    // dropped chunk leaves a hole), and the chunk's own length where the clock jumped
    // back to the bag's start and the renderer's timeline restarted.
    const double chunk_s = rate > 0.0 ? static_cast<double>(chunk_frames) / rate : 0.0;
    if (window_chunks == 0) {
      window_first_chunk = now;
      window_bag_s = chunk_s;
    } else {
      window_bag_s += m->header.stamp > window_last_stamp ? (m->header.stamp - window_last_stamp).toSec() : chunk_s;
    }
    window_last_stamp = m->header.stamp;
    window_frames += chunk_frames;
    ++window_chunks;
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

  // The stream from now on: its audio, the bag's time that audio spans, when the first
  // chunk came and the longest wall-clock wait between chunks.
  void startWindow() {
    std::lock_guard<std::mutex> lock(mutex);
    window_start = gap_from = ros::WallTime::now();
    window_frames = window_chunks = 0;
    window_max_gap_s = window_bag_s = 0.0;
  }
  struct Window {
    double wall_s, audio_s, bag_s, max_gap_s;
    std::size_t chunks;
    ros::WallTime first_chunk;
  };
  Window window() {
    std::lock_guard<std::mutex> lock(mutex);
    const ros::WallTime now = ros::WallTime::now();
    return {(now - window_start).toSec(), rate > 0.0 ? static_cast<double>(window_frames) / rate : 0.0, window_bag_s,
            std::max(window_max_gap_s, (now - gap_from).toSec()), window_chunks, window_first_chunk};
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
  ros::WallTime window_start, gap_from, window_first_chunk;
  ros::Time window_last_stamp;
  std::size_t window_frames = 0, window_chunks = 0;
  double window_max_gap_s = 0.0, window_bag_s = 0.0;
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

// ---- Faults: every node of the graph killed in turn.

// Polls `condition` until it holds or `timeout_s` of wall time passed.
template <typename F>
bool waitUntil(F condition, double timeout_s) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::WallTime::now() < deadline) {
    if (condition()) return true;
    ros::WallDuration(0.1).sleep();
  }
  return condition();
}

double wallSince(const ros::WallTime& start) { return (ros::WallTime::now() - start).toSec(); }

// The nodes under `ns` that the test's own master knows. Pids, and so kills, come from
// this master and the nodes themselves, never from process names: another graph on the
// machine may run nodes of the same names.
std::set<std::string> graphNodes(const std::string& ns) {
  std::set<std::string> nodes;
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  if (!ros::master::execute("getSystemState", args, result, payload, false)) return nodes;
  for (int kind = 0; kind < payload.size(); ++kind) {
    for (int entry = 0; entry < payload[kind].size(); ++entry) {
      XmlRpc::XmlRpcValue& names = payload[kind][entry][1];
      for (int k = 0; k < names.size(); ++k) {
        const std::string name = static_cast<std::string>(names[k]);
        if (name.rfind(ns, 0) == 0) nodes.insert(name);
      }
    }
  }
  return nodes;
}

// Calls `method` of the node's own XML-RPC API; false when the node does not answer (a
// killed node's registration stays with the master until its respawn replaces it).
bool callNode(const std::string& node, const char* method, XmlRpc::XmlRpcValue& payload) {
  XmlRpc::XmlRpcValue args, result, uri;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, uri, false)) return false;
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(uri), host, port)) return false;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue call_args, answer;
  call_args[0] = ros::this_node::getName();
  if (!client.execute(method, call_args, answer) || client.isFault()) return false;
  if (answer.getType() != XmlRpc::XmlRpcValue::TypeArray || answer.size() != 3 || static_cast<int>(answer[0]) != 1) {
    return false;
  }
  payload = answer[2];
  return true;
}

// The node's process id, as the node tells it; 0 when it does not answer.
int nodePid(const std::string& node) {
  XmlRpc::XmlRpcValue pid;
  if (!callNode(node, "getPid", pid) || pid.getType() != XmlRpc::XmlRpcValue::TypeInt) return 0;
  return static_cast<int>(pid);
}

// The topics the node's process publishes, as it tells them.
std::set<std::string> nodePublications(const std::string& node) {
  std::set<std::string> topics;
  XmlRpc::XmlRpcValue publications;
  if (!callNode(node, "getPublications", publications)) return topics;
  for (int k = 0; k < publications.size(); ++k) topics.insert(static_cast<std::string>(publications[k][0]));
  return topics;
}

// The first message on `topic` to a subscriber made now (a latched one arrives at once);
// null when none came within `timeout_s`. Fresh only if the process has no other
// subscriber of `topic`.
template <typename M>
boost::shared_ptr<const M> firstMessage(const std::string& topic, double timeout_s) {
  struct Inbox {
    std::mutex mutex;
    boost::shared_ptr<const M> message;
  };
  const auto inbox = std::make_shared<Inbox>();
  const boost::function<void(const boost::shared_ptr<const M>&)> keep = [inbox](const boost::shared_ptr<const M>& m) {
    std::lock_guard<std::mutex> lock(inbox->mutex);
    if (!inbox->message) inbox->message = m;
  };
  ros::NodeHandle nh;
  const ros::Subscriber sub = nh.subscribe<M>(topic, 1, keep);
  boost::shared_ptr<const M> message;
  waitUntil(
      [&] {
        std::lock_guard<std::mutex> lock(inbox->mutex);
        message = inbox->message;
        return message != nullptr;
      },
      timeout_s);
  return message;
}

// A node's latched topic, fetched by a fresh subscriber, as the numbers that identify its
// content: the same before the kill and after the respawn (the bag is the same pass after
// pass). Empty when nothing arrived in time.
struct LatchedState {
  std::string topic;
  std::function<std::vector<double>(double timeout_s)> fetch;
};

template <typename M>
LatchedState latched(const std::string& topic, std::function<std::vector<double>(const M&)> numbers) {
  return {topic, [topic, numbers](double timeout_s) {
            const boost::shared_ptr<const M> m = firstMessage<M>(topic, timeout_s);
            return m ? numbers(*m) : std::vector<double>{};
          }};
}

std::vector<double> imageNumbers(const sensor_msgs::Image& m) {
  return {double(m.width), double(m.height), double(m.step)};
}

std::string joined(const std::vector<double>& values) {
  std::ostringstream out;
  for (std::size_t k = 0; k < values.size(); ++k) out << (k ? ", " : "") << values[k];
  return out.str();
}

// One node of the graph and what it must do again after a SIGKILL and its respawn.
struct NodeFault {
  std::string node;
  std::vector<std::string> topics;    // publishes these again
  std::vector<std::string> services;  // offers these again (besides ~get_loggers, as every node)
  std::vector<LatchedState> states;   // re-publishes these, latched
  // From the respawn to the first re-published state. A node fed straight from the bag
  // (one capture and one RIR per pass) waits for the next pass; one fed by latched
  // topics gets its inputs, and re-publishes, at once.
  double republish_within_s;
  // Asks it to do its job: "" when it did, else what went wrong. Null: its states say it.
  std::function<std::string()> serves;
};

std::vector<NodeFault> replayGraphFaults() {
  // The bag lasts 10 s; its capture then goes through capture_ingest (and spherical_depth)
  // on slow, maybe busy, cores.
  const double next_pass_s = 30.0;
  const double at_once_s = 20.0;
  return {
      {"/rig/capture_ingest",
       {"/rig/top/image_equirect", "/rig/bottom/image_equirect", "/rig/rig_tilt"},
       {},
       {latched<sensor_msgs::Image>("/rig/top/image_equirect", imageNumbers),
        latched<sensor_msgs::Image>("/rig/bottom/image_equirect", imageNumbers)},
       next_pass_s,
       nullptr},
      {"/rig/spherical_depth",
       {"/rig/points", "/rig/range_image"},
       {"/rig/spherical_depth/set_parameters"},
       {latched<sensor_msgs::PointCloud2>("/rig/points",
                                          [](const sensor_msgs::PointCloud2& m) {
                                            return std::vector<double>{double(m.width) * m.height};
                                          }),
        latched<sensor_msgs::Image>("/rig/range_image", imageNumbers)},
       at_once_s,
       nullptr},
      {"/rig/room_model",
       {"/rig/room_model/room", "/rig/room_model/markers"},
       {"/rig/room_model/build"},
       {latched<room_reverb::RoomModel>(
           "/rig/room_model/room",
           [](const room_reverb::RoomModel& m) {
             return std::vector<double>{m.size.x, m.size.y, m.size.z, double(m.objects.size())};
           })},
       at_once_s,
       []() -> std::string {
         // Answered from the room it built on the latched cloud.
         room_reverb::BuildRoomModel srv;
         if (!ros::service::call("/rig/room_model/build", srv)) return "no answer from ~build";
         if (!srv.response.success) return srv.response.message;
         const core::RoomModel truth =
             core::loadRoomModel(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/sample_room/visible.yaml");
         const double got[3] = {srv.response.room.size.x, srv.response.room.size.y, srv.response.room.size.z};
         for (int k = 0; k < 3; ++k) {
           if (std::abs(got[k] - truth.size_m[k]) > std::max(0.03, 0.01 * truth.size_m[k])) {
             return "room axis " + std::to_string(k) + ": " + std::to_string(got[k]) + " m, the bag's room " +
                    std::to_string(truth.size_m[k]) + " m";
           }
         }
         return "";
       }},
      {"/rig/room_simulator",
       {},
       {"/rig/room_simulator/simulate"},
       {},
       at_once_s,
       []() -> std::string {
         const auto room = firstMessage<room_reverb::RoomModel>("/rig/room_model/room", 5.0);
         if (!room) return "no room on /rig/room_model/room to simulate";
         room_reverb::SimulateRoom srv;
         srv.request.room = *room;
         srv.request.source.x = srv.request.source.y = 1.0;
         srv.request.source.z = 1.5;
         srv.request.listener.x = room->size.x - 1.5;
         srv.request.listener.y = room->size.y - 1.5;
         srv.request.listener.z = 1.5;
         srv.request.mode = "eyring";  // image sources and a formula: quick
         srv.request.image_source_order = 1;
         srv.request.duration_s = 0.3;
         if (!ros::service::call("/rig/room_simulator/simulate", srv)) return "no answer from ~simulate";
         if (!srv.response.success) return srv.response.message;
         const room_reverb::AudioBuffer& ir = srv.response.impulse_response.audio;
         const double seconds = ir.sample_rate_hz > 0.0 && ir.channel_count > 0
                                    ? static_cast<double>(ir.samples.size()) / ir.channel_count / ir.sample_rate_hz
                                    : 0.0;
         if (std::abs(seconds - 0.3) > 0.05) return "a " + std::to_string(seconds) + " s response to a 0.3 s request";
         return "";
       }},
      {"/rig/rsao_estimator",
       {"/rig/rsao_estimator/rsao", "/rig/rsao_estimator/markers"},
       {"/rig/rsao_estimator/estimate"},
       {latched<room_reverb::Rsao>("/rig/rsao_estimator/rsao",
                                   [](const room_reverb::Rsao& m) {
                                     return std::vector<double>{double(m.reflections.size()), m.late.mixing_time_s};
                                   })},
       next_pass_s,
       []() -> std::string {
         room_reverb::EstimateRsao srv;
         srv.request.file = bagDir() + "/measured_rir.wav";
         srv.request.format = "ambix";
         if (!ros::service::call("/rig/rsao_estimator/estimate", srv)) return "no answer from ~estimate";
         if (!srv.response.success) return srv.response.message;
         if (srv.response.rsao.reflections.size() <= 3u) {
           return std::to_string(srv.response.rsao.reflections.size()) + " reflections";
         }
         return "";
       }},
      {"/rig/binaural_renderer",
       {"/rig/binaural_renderer/binaural", "/rig/binaural_renderer/status"},
       {"/rig/binaural_renderer/render_to_file"},
       {latched<room_reverb::StreamStatus>(
           "/rig/binaural_renderer/status",
           [](const room_reverb::StreamStatus& m) {
             return std::vector<double>{m.sample_rate_hz, double(m.chunk_frames), double(m.block_frames)};
           })},
       at_once_s,
       nullptr},
  };
}

TEST(Replay, EveryKilledNodeRespawnsRepublishesAndTheStreamKeepsGoing) {
  Listener& l = listener();
  ASSERT_TRUE(l.waitFor([&] { return l.chunks > 20; }, 60.0)) << "no binaural chunks";
  // roscpp shares one subscription per topic within a process, and that subscription keeps
  // a killed publisher's latched message until the master's update about the respawned
  // one reaches it. Each fetch of a latched state below must be the process's only
  // subscriber of its topic, registered with the master afresh.
  l.cloud_sub.shutdown();  // not under l.mutex: shutdown waits for a callback that takes it
  l.rsao_sub.shutdown();
  l.status_sub.shutdown();
  const std::vector<NodeFault> faults = replayGraphFaults();
  // Every node of the graph has its case: a node added to the graph fails here until it has.
  std::set<std::string> cases;
  for (const NodeFault& f : faults) cases.insert(f.node);
  EXPECT_EQ(graphNodes("/rig/"), cases);
  std::map<std::string, int> pids;
  for (const NodeFault& f : faults) {
    pids[f.node] = nodePid(f.node);
    ASSERT_GT(pids[f.node], 0) << f.node << " does not tell its pid";
  }

  for (const NodeFault& f : faults) {
    const bool renderer = f.node == "/rig/binaural_renderer";
    std::vector<std::vector<double>> before;
    for (const LatchedState& s : f.states) {
      before.push_back(s.fetch(5.0));
      ASSERT_FALSE(before.back().empty()) << f.node << ": nothing latched on " << s.topic << " before the kill";
    }

    l.startWindow();
    const ros::WallTime killed = ros::WallTime::now();
    ASSERT_EQ(::kill(pids[f.node], SIGKILL), 0) << f.node << " (pid " << pids[f.node] << ") could not be killed";
    int pid = 0;
    ASSERT_TRUE(waitUntil(
        [&] {
          pid = nodePid(f.node);
          return pid != 0 && pid != pids[f.node];
        },
        20.0))
        << f.node << " did not come back within 20 s of its SIGKILL";
    const double respawn_s = wallSince(killed);
    pids[f.node] = pid;
    const ros::WallTime respawned = ros::WallTime::now();
    // The killed renderer's last chunks are in by now: any chunk from here on is the new one's.
    if (renderer) l.startWindow();

    std::set<std::string> published;
    waitUntil(
        [&] {
          published = nodePublications(f.node);
          return std::all_of(f.topics.begin(), f.topics.end(),
                             [&](const std::string& topic) { return published.count(topic) > 0; });
        },
        10.0);
    for (const std::string& topic : f.topics) {
      EXPECT_EQ(published.count(topic), 1u) << f.node << " does not publish " << topic << " after its respawn";
    }
    std::vector<std::string> services = f.services;
    services.push_back(f.node + "/get_loggers");
    for (const std::string& service : services) {
      EXPECT_TRUE(ros::service::waitForService(service, ros::Duration(10.0)))
          << f.node << " does not offer " << service << " after its respawn";
    }

    // Its state again, live or latched; then a second fresh subscriber gets it latched.
    double republish_s = 0.0;
    for (std::size_t k = 0; k < f.states.size(); ++k) {
      const LatchedState& s = f.states[k];
      const std::vector<double> first = s.fetch(std::max(1.0, f.republish_within_s - wallSince(respawned)));
      EXPECT_FALSE(first.empty()) << f.node << " did not re-publish " << s.topic << " within "
                                  << f.republish_within_s << " s of its respawn";
      if (first.empty()) continue;
      republish_s = std::max(republish_s, wallSince(killed));
      const std::vector<double> again = s.fetch(5.0);
      ASSERT_EQ(again.size(), before[k].size()) << f.node << " re-published " << s.topic << " but not latched";
      for (std::size_t i = 0; i < again.size(); ++i) {
        EXPECT_NEAR(again[i], before[k][i], 1e-3 * std::abs(before[k][i]))
            << f.node << ": " << s.topic << " [" << joined(again) << "] after the respawn, [" << joined(before[k])
            << "] before";
      }
    }
    if (f.serves) {
      EXPECT_EQ(f.serves(), "") << f.node << " does not do its job after its respawn";
    }

    // The stream: it flows while another node is down, covering the bag's time; once the
    // renderer itself is back, it flows so again. Measured on the bag's clock: on busy
    // cores rosbag play itself falls behind the wall clock. Not all of it: while
    // spherical_depth and room_model redo the capture, a renderer starved of its core by
    // other work on the machine drops chunks (a fifth of them on two cores under a build).
    double resumed_s = 0.0;
    if (renderer) {
      EXPECT_TRUE(l.waitFor([&] { return l.window_chunks > 0; }, 20.0)) << "the stream did not resume";
      resumed_s = (l.window().first_chunk - killed).toSec();
      l.startWindow();
    }
    const double watch_s = 3.0;  // at least, for a rate
    ros::WallDuration(renderer ? watch_s : std::max(0.0, watch_s - wallSince(killed))).sleep();
    const Listener::Window w = l.window();
    const std::string streamed = std::to_string(w.audio_s) + " s of audio over " + std::to_string(w.bag_s) +
                                 " s of the bag, " + f.node + " killed";
    EXPECT_GT(w.audio_s, 0.7 * w.bag_s) << streamed;
    EXPECT_LT(w.audio_s, w.bag_s + 0.01) << streamed;
    EXPECT_LT(w.max_gap_s, 2.0) << "a " << w.max_gap_s << " s gap between chunks, " << f.node << " killed";

    for (const NodeFault& other : faults) {
      if (other.node == f.node) continue;
      EXPECT_EQ(nodePid(other.node), pids[other.node]) << other.node << " died while " << f.node << " was killed";
    }

    std::printf("killed %s: back in %.2f s; state re-published %.2f s after the kill (0: none latched); stream %.2f s "
                "of audio over %.2f s of the bag and %.2f s of wall time, longest gap %.2f s; renderer's stream "
                "resumed %.2f s after the kill (0: not it)\n",
                f.node.c_str(), respawn_s, republish_s, w.audio_s, w.bag_s, w.wall_s, w.max_gap_s, resumed_s);
    const std::string key = f.node.substr(f.node.rfind('/') + 1);
    ::testing::Test::RecordProperty(key + "_respawn_s", std::to_string(respawn_s));
    ::testing::Test::RecordProperty(key + "_republish_s", std::to_string(republish_s));
    ::testing::Test::RecordProperty(key + "_stream_gap_s", std::to_string(renderer ? resumed_s : w.max_gap_s));
  }
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
