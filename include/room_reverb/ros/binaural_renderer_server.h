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
// the room_simulator's service), ~head_orientation (geometry_msgs/QuaternionStamped),
// ~listener_pose (geometry_msgs/PoseStamped: position and orientation in the room frame),
// ~room_model (RoomModel, with TF ~room_frame -> ~rig_frame: the room an RSAO is walked in),
// TF ~room_frame -> ~listener_frame (the listener's head, when that parameter is set);
// ~binaural (AudioBuffer out, "binaural", 48 kHz), ~status (StreamStatus, latched),
// ~markers (visualization_msgs/MarkerArray: the walking listener for rviz).
// With ~jack_output the same samples also play through a JACK client, whose sound card
// then paces the stream (binaural_renderer_jack.cpp).
// Service: ~render_to_file (RenderToFile). Parameters: config/binaural_renderer.yaml.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/QuaternionStamped.h>
#include <ros/ros.h>
#include <room_reverb/AudioBuffer.h>
#include <room_reverb/ImpulseResponse.h>
#include <room_reverb/RenderToFile.h>
#include <room_reverb/RoomModel.h>
#include <room_reverb/RoomScene.h>
#include <room_reverb/Rsao.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <memory>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "room_reverb/audio/jack_output.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/binaural_stream.h"
#include "room_reverb/binaural/reflection_tap_bank.h"
#include "room_reverb/binaural/source_feed.h"
#include "room_reverb/binaural/walk_render.h"
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
  void onListenerPose(const geometry_msgs::PoseStamped::ConstPtr& message);
  void onRoomModel(const room_reverb::RoomModel::ConstPtr& message);

 private:
  struct Counters {
    std::uint64_t room_changes = 0;
    std::uint64_t rooms_rejected = 0;
    std::uint64_t orientations_rejected = 0;
    std::uint64_t listener_positions_clamped = 0;
    std::string last_message;
  };

  // A new room for the audio thread; with `rsao_generation`, only if no later RSAO has
  // been offered meanwhile (callbacks run on two threads: an RSAO prepared without the
  // room model must not replace one prepared with it).
  void offerRoom(StreamRoom room, std::optional<std::uint64_t> rsao_generation = std::nullopt);
  void rejectRoom(const std::string& why);
  void note(const std::string& message, bool warning);  // last_message and the log
  void audioLoop();
  void renderChunk();
  // Six degrees of freedom (binaural_renderer_listener.cpp): an RSAO offered as a room a
  // listener walks in when a room model is known (the last RSAO is offered again when the
  // model changes).
  void offerRsao(const core::Rsao& rsao, const std::string& what);
  // Audio thread: a new room's taps, and the taps' targets for a listener position.
  void takeRoomTaps(const StreamRoom& room);
  // A listener pose from ~listener_pose or TF (`from` names which, for the log), stamped
  // `stamp` (zero: not stamped).
  void acceptListenerPose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation, const char* from,
                          const ::ros::Time& stamp);
  // Timer: the newest TF room_frame -> listener_frame, when ~listener_frame is set.
  void followListenerFrame();
  // Timer: ~markers of the walkable room playing (listener, image sources, paths heard).
  void publishMarkers();
  // The taps' targets for a listener at `wanted`, clamped into the room model (counted and
  // warned); nothing where the translation refuses the position (inside an object: the
  // taps stay where they were).
  std::optional<std::vector<core::TapTarget>> tapTargetsFor(const Eigen::Vector3d& wanted);
  void publishStatus();
  // JACK output (binaural_renderer_jack.cpp): the parameters and the retry timer; joining
  // the server (timer thread); on the audio thread, taking a new client over or dropping
  // one whose server went away, and the stream's clock (the card's while JACK plays, ROS
  // time otherwise).
  void setUpJack(::ros::NodeHandle& private_nh);
  // The simulated route walked (binaural_renderer_simulated_walk.cpp): parameters, worker
  // and refresh timer; a scene simulated and offered (walkable when it can be); the late
  // part simulated again where the listener has walked to; the worker's loop.
  void setUpSimulatedWalk(::ros::NodeHandle& private_nh);
  void playScene(const room_reverb::RoomScene& scene, std::uint64_t generation);
  void refreshWalk();
  void earlyLoop();
  void joinJack();
  void takeJack();
  double streamClock() const;

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
  // The oldest pose time (StreamStatus::pose_to_ear_s) the chunk being rendered took, and
  // the longest pose-to-ear time since the last status.
  std::optional<double> taken_pose_s_;
  double worst_pose_to_ear_s_ = 0.0;
  std::uint64_t chunks_at_mark_ = 0;
  std::string audio_scheduling_;
  std::shared_ptr<const core::ListenerTranslation> translation_;  // of the room playing
  std::shared_ptr<const core::RoomModel> taps_room_model_;
  std::shared_ptr<const core::SimulatedWalk> early_walk_;  // of the room playing
  core::PreparedResponse no_early_;  // removes the early part of the last walkable room
  Eigen::Vector3d listener_from_ = Eigen::Vector3d::Zero(), listener_to_ = Eigen::Vector3d::Zero();
  // The taps' targets where the last chunk ended, where this one ends, and one block's
  // blend of the two (audio thread; reused so that a walking chunk allocates little).
  core::ChunkedTapTargets walk_targets_;
  bool listener_known_ = false;
  std::shared_ptr<core::JackOutput> jack_;
  double jack_epoch_s_ = 0.0;  // stream time at the client's first frame
  core::JackOutputCounters jack_counts_before_;  // of clients whose server went away

  // Shared, under mutex_.
  std::mutex mutex_;
  std::unique_ptr<core::SourceQueue> source_queue_;  // topic mode
  std::shared_ptr<const StreamRoom> pending_room_;
  std::shared_ptr<const StreamRoom> current_room_;
  std::optional<Eigen::Quaterniond> pending_head_;
  std::optional<Eigen::Vector3d> pending_position_;
  std::optional<double> pending_pose_s_;  // the oldest pending pose's time (ROS seconds)
  std::optional<Eigen::Vector3d> last_listener_position_;  // for ~render_to_file and ~markers
  Eigen::Quaterniond last_head_ = Eigen::Quaterniond::Identity();  // for ~markers
  bool markers_shown_ = false;  // ~markers holds a listener (cleared when the room stops being walkable)
  std::shared_ptr<const core::RoomModel> walkable_room_;
  std::optional<std::pair<core::Rsao, std::string>> last_rsao_;
  std::uint64_t rsao_generation_ = 0;
  Counters counters_;
  std::shared_ptr<core::JackOutput> pending_jack_;
  // A client whose server went away, closed on the retry timer's thread (jack_client_close
  // may block, and the audio thread must not).
  std::shared_ptr<core::JackOutput> retired_jack_;
  // An image-source part for the audio thread, and the walk it belongs to.
  struct PendingEarly {
    std::shared_ptr<const core::SimulatedWalk> walk;
    core::PreparedResponse early;
  };
  std::shared_ptr<const PendingEarly> pending_early_;
  room_reverb::RoomScene::ConstPtr last_scene_;
  std::uint64_t scene_generation_ = 0;
  std::string jack_state_ = "off";
  std::string jack_lost_;  // why the last server went away, until one is joined

  std::atomic<bool> running_{false};
  std::atomic<bool> jack_playing_{false};
  core::JackOutputOptions jack_options_;
  ::ros::WallTimer jack_timer_, refresh_timer_;
  bool walk_room_scenes_ = true;
  double walk_refresh_m_ = 2.0;
  core::MaterialLibrary library_;
  bool early_running_ = false;                 // under mutex_
  std::condition_variable early_wake_;        // a pose, a room or stop() for earlyLoop
  std::thread early_thread_;
  std::thread audio_thread_;

  ::ros::NodeHandle nh_;
  ::ros::Publisher binaural_publisher_, status_publisher_;
  ::ros::Subscriber source_sub_, rsao_sub_, impulse_response_sub_, room_scene_sub_, head_sub_;
  ::ros::Subscriber listener_pose_sub_, room_model_sub_;
  std::string room_frame_, rig_frame_, listener_frame_;
  ::ros::WallTimer listener_timer_, marker_timer_;
  ::ros::Publisher marker_publisher_;
  ::ros::Time last_listener_tf_stamp_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ::ros::ServiceServer render_server_;
  ::ros::ServiceClient simulator_;
};

}  // namespace room_reverb::ros_bridge
