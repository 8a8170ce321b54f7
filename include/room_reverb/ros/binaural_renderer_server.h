#pragma once
// The binaural_renderer node's body: a dry source heard in the current room, head-tracked,
// streamed as binaural AudioBuffer chunks in real time (by ROS time: the wall clock live,
// /clock during a bag replay).
//
// Threads: ROS callbacks (a multi-threaded spinner) prepare rooms (resynthesis, a call to
// the simulator) and hand them over; one audio thread owns the BinauralStream, paces,
// renders, publishes. The hand-over is a pointer swap under a short lock, so a slow room
// never stalls the audio; the swap itself (the convolver's new partitions, some 15 ms for a
// 2 s third-order room) runs on the audio thread and can make a chunk or two late, which
// ~status counts honestly.
//
// Topics (private namespace): ~source (AudioBuffer in; unless ~source_file is set),
// ~rsao (Rsao), ~impulse_response (ImpulseResponse), ~room_scene (RoomScene, simulated by
// the room_simulator's service), ~head_orientation (geometry_msgs/QuaternionStamped);
// ~binaural (AudioBuffer out, "binaural", 48 kHz), ~status (StreamStatus, latched).
// Service: ~render_to_file (RenderToFile). Parameters: config/binaural_renderer.yaml.
#include <geometry_msgs/QuaternionStamped.h>
#include <ros/ros.h>
#include <room_reverb/AudioBuffer.h>
#include <room_reverb/ImpulseResponse.h>
#include <room_reverb/RenderToFile.h>
#include <room_reverb/RoomScene.h>
#include <room_reverb/Rsao.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/binaural_stream.h"
#include "room_reverb/binaural/source_feed.h"
#include "room_reverb/binaural/stream_pacer.h"
#include "room_reverb/ros/binaural_room_inputs.h"

namespace room_reverb::ros_bridge {

class BinauralRendererServer {
 public:
  // Reads and checks the parameters, loads the HRTFs and the initial room and source;
  // throws InputError for bad ones. The audio thread starts with start().
  BinauralRendererServer(::ros::NodeHandle& nh, ::ros::NodeHandle& private_nh);
  ~BinauralRendererServer();

  void start();
  void stop();

  // Service and callbacks, public for tests; none throws.
  bool renderToFile(room_reverb::RenderToFile::Request& request, room_reverb::RenderToFile::Response& response);
  void onSource(const room_reverb::AudioBuffer::ConstPtr& message);
  void onRsao(const room_reverb::Rsao::ConstPtr& message);
  void onImpulseResponse(const room_reverb::ImpulseResponse::ConstPtr& message);
  void onRoomScene(const room_reverb::RoomScene::ConstPtr& message);
  void onHeadOrientation(const geometry_msgs::QuaternionStamped::ConstPtr& message);

 private:
  struct Counters {
    std::uint64_t room_changes = 0;
    std::uint64_t rooms_rejected = 0;
    std::uint64_t orientations_rejected = 0;
    std::string last_message;
  };

  void offerRoom(StreamRoom room);                // a new room for the audio thread
  void rejectRoom(const std::string& why);
  void note(const std::string& message, bool warning);  // last_message and the log
  void audioLoop();
  void renderChunk();
  void publishStatus();

  // Configuration.
  std::string frame_id_;
  std::string source_description_;
  std::size_t block_frames_ = 256;
  std::size_t chunk_blocks_ = 2;
  std::uint32_t rsao_seed_ = 1;
  double status_period_s_ = 1.0;
  int realtime_priority_ = 10;
  std::string simulator_service_;
  core::StreamPacerOptions pacer_options_;

  // The decoder: read-only after construction (also used by ~render_to_file).
  core::BinauralDecoder decoder_;

  // Owned by the audio thread.
  std::unique_ptr<core::BinauralStream> stream_;
  std::unique_ptr<core::StreamPacer> pacer_;
  std::unique_ptr<core::LoopedSource> looped_source_;
  std::vector<float> source_block_, left_, right_;
  room_reverb::AudioBuffer chunk_message_;
  // At the last status: processor times and chunks published; the longest chunk since.
  double cpu_thread_mark_ = 0.0, cpu_process_mark_ = 0.0, worst_chunk_s_ = 0.0;
  std::uint64_t chunks_at_mark_ = 0;
  std::string audio_scheduling_;

  // Shared, under mutex_.
  std::mutex mutex_;
  std::unique_ptr<core::SourceQueue> source_queue_;  // topic mode
  std::shared_ptr<const StreamRoom> pending_room_;
  std::shared_ptr<const StreamRoom> current_room_;
  std::optional<Eigen::Quaterniond> pending_head_;
  Counters counters_;

  std::atomic<bool> running_{false};
  std::thread audio_thread_;

  ::ros::NodeHandle nh_;
  ::ros::Publisher binaural_publisher_, status_publisher_;
  ::ros::Subscriber source_sub_, rsao_sub_, impulse_response_sub_, room_scene_sub_, head_sub_;
  ::ros::ServiceServer render_server_;
  ::ros::ServiceClient simulator_;
};

}  // namespace room_reverb::ros_bridge
