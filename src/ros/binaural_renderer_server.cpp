#include "room_reverb/ros/binaural_renderer_server.h"

#include <room_reverb/SimulateRoom.h>
#include <room_reverb/StreamStatus.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>

#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/audio/partitioned_convolver.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/common/error.h"
#include "room_reverb/ros/parameters.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/rsao_conversions.h"

namespace room_reverb::ros_bridge {

BinauralRendererServer::BinauralRendererServer(::ros::NodeHandle& nh, ::ros::NodeHandle& private_nh)
    : nh_(nh) {
  std::string hrtf_file, decoder_name, source_file, room_file, room_format;
  typedParam(private_nh, "frame_id", frame_id_, std::string("head"));
  typedParam(private_nh, "hrtf_file", hrtf_file, std::string(""));
  typedParam(private_nh, "decoder", decoder_name, std::string("magls"));
  const int order = positiveIntParam(private_nh, "order", 3);
  if (order > 3) throw core::InputError("parameter ~order must be 1 to 3");
  block_frames_ = static_cast<std::size_t>(positiveIntParam(private_nh, "block_frames", 256));
  chunk_blocks_ = static_cast<std::size_t>(positiveIntParam(private_nh, "chunk_blocks", 2));
  core::BinauralStreamOptions stream_options;
  stream_options.block_size = block_frames_;
  stream_options.crossfade_blocks = static_cast<std::size_t>(positiveIntParam(private_nh, "crossfade_blocks", 4));
  typedParam(private_nh, "max_response_s", stream_options.max_response_s, 4.0);
  typedParam(private_nh, "mixed_order_late", stream_options.mixed_order_late, false);
  typedParam(private_nh, "full_order_s", stream_options.full_order_s, 0.1);
  const double chunk_period_s = static_cast<double>(block_frames_ * chunk_blocks_) / core::kInternalSampleRateHz;
  pacer_options_.chunk_period_s = chunk_period_s;
  typedParam(private_nh, "late_tolerance_s", pacer_options_.late_tolerance_s, chunk_period_s);
  typedParam(private_nh, "max_lag_s", pacer_options_.max_lag_s, 0.25);
  typedParam(private_nh, "status_period_s", status_period_s_, 1.0);
  if (!(status_period_s_ > 0.0)) throw core::InputError("parameter ~status_period_s must be positive");
  typedParam(private_nh, "realtime_priority", realtime_priority_, 10);
  if (realtime_priority_ < 0 || realtime_priority_ > 99) {
    throw core::InputError("parameter ~realtime_priority must be 0 (normal scheduling) to 99");
  }
  rsao_seed_ = static_cast<std::uint32_t>(positiveIntParam(private_nh, "rsao_seed", 1));
  typedParam(private_nh, "simulator_service", simulator_service_, std::string("room_simulator/simulate"));
  typedParam(private_nh, "source_file", source_file, std::string(""));
  double prebuffer_s = 0.05, max_queued_s = 1.0;
  typedParam(private_nh, "source_prebuffer_s", prebuffer_s, 0.05);
  typedParam(private_nh, "source_max_queued_s", max_queued_s, 1.0);
  typedParam(private_nh, "room_file", room_file, std::string(""));
  typedParam(private_nh, "room_format", room_format, std::string("fuma"));
  std::string room_model_file;
  typedParam(private_nh, "room_model_file", room_model_file, std::string(""));
  typedParam(private_nh, "room_frame", room_frame_, std::string("room"));
  typedParam(private_nh, "rig_frame", rig_frame_, std::string("rig"));
  typedParam(private_nh, "listener_frame", listener_frame_, std::string(""));
  double listener_tf_period_s = 0.005;
  typedParam(private_nh, "listener_tf_period_s", listener_tf_period_s, 0.005);
  if (!(listener_tf_period_s >= 0.001 && listener_tf_period_s <= 1.0)) {
    throw core::InputError("parameter ~listener_tf_period_s must be 0.001 to 1 s");
  }
  if (!room_model_file.empty()) walkable_room_ = std::make_shared<const core::RoomModel>(core::loadRoomModel(room_model_file));

  const core::HrtfSet hrtf =
      core::HrtfSet::loadSofa(hrtf_file.empty() ? core::HrtfSet::defaultSofaPath() : hrtf_file);
  for (const std::string& n : hrtf.notes()) ROS_INFO("binaural_renderer: %s", n.c_str());
  decoder_ = core::makeBinauralDecoder(hrtf, order, core::parseDecoderMethod(decoder_name));
  stream_ = std::make_unique<core::BinauralStream>(decoder_, stream_options);
  no_early_ = stream_->prepareEarlyResponse(core::AudioBuffer());
  pacer_ = std::make_unique<core::StreamPacer>(pacer_options_);
  source_block_.assign(block_frames_, 0.0f);
  left_.assign(block_frames_ * chunk_blocks_, 0.0f);
  right_ = left_;

  if (!source_file.empty()) {
    looped_source_ = std::make_unique<core::LoopedSource>(core::readAudioFile(source_file));
    source_description_ = "file " + source_file;
  } else {
    source_queue_ = std::make_unique<core::SourceQueue>(prebuffer_s, max_queued_s);
    source_description_ = "topic";
  }
  if (!room_file.empty()) {
    StreamRoom room = roomFromFile(room_file, room_format, rsao_seed_, room_format == "rsao" ? walkable_room_ : nullptr);
    for (const std::string& n : room.notes) ROS_INFO("binaural_renderer: %s", n.c_str());
    // Set before the audio thread starts, so the first chunk is not late for it.
    const std::string warning = stream_->setRoom(room.ambix);
    if (!warning.empty()) note(warning, true);
    takeRoomTaps(room);
    current_room_ = std::make_shared<const StreamRoom>(std::move(room));
    counters_.room_changes = 1;
  }

  binaural_publisher_ = private_nh.advertise<room_reverb::AudioBuffer>("binaural", 50);
  status_publisher_ = private_nh.advertise<room_reverb::StreamStatus>("status", 1, true);
  if (source_queue_) source_sub_ = private_nh.subscribe("source", 50, &BinauralRendererServer::onSource, this);
  rsao_sub_ = private_nh.subscribe("rsao", 1, &BinauralRendererServer::onRsao, this);
  impulse_response_sub_ = private_nh.subscribe("impulse_response", 1, &BinauralRendererServer::onImpulseResponse, this);
  room_scene_sub_ = private_nh.subscribe("room_scene", 1, &BinauralRendererServer::onRoomScene, this);
  head_sub_ = private_nh.subscribe("head_orientation", 10, &BinauralRendererServer::onHeadOrientation, this);
  listener_pose_sub_ = private_nh.subscribe("listener_pose", 10, &BinauralRendererServer::onListenerPose, this);
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
  room_model_sub_ = private_nh.subscribe("room_model", 1, &BinauralRendererServer::onRoomModel, this);
  double marker_period_s = 0.1;
  typedParam(private_nh, "marker_period_s", marker_period_s, 0.1);
  if (!(marker_period_s >= 0.0 && marker_period_s <= 60.0)) throw core::InputError("parameter ~marker_period_s must be 0 (off) to 60 s");
  marker_publisher_ = private_nh.advertise<visualization_msgs::MarkerArray>("markers", 1);
  if (marker_period_s > 0.0) {
    marker_timer_ = private_nh.createWallTimer(::ros::WallDuration(marker_period_s),
                                               [this](const ::ros::WallTimerEvent&) { publishMarkers(); });
  }
  if (!listener_frame_.empty()) {
    listener_timer_ = private_nh.createWallTimer(::ros::WallDuration(listener_tf_period_s),
                                                 [this](const ::ros::WallTimerEvent&) { followListenerFrame(); });
  }
  render_server_ = private_nh.advertiseService("render_to_file", &BinauralRendererServer::renderToFile, this);
  simulator_ = nh_.serviceClient<room_reverb::SimulateRoom>(simulator_service_);
  setUpJack(private_nh);
  setUpSimulatedWalk(private_nh);
  // Every transform size the streaming convolvers can use, measured before the audio
  // thread starts (fft.h): a room that arrives later is prepared without the audio thread
  // waiting on FFTW's planner.
  core::prepareMeasuredFftPlans(2 * block_frames_, 2 * core::PartitionedConvolver::kDefaultMaxPartitionSize);
}

BinauralRendererServer::~BinauralRendererServer() { stop(); }

void BinauralRendererServer::start() {
  if (running_.exchange(true)) return;
  audio_thread_ = std::thread([this] { audioLoop(); });
}

void BinauralRendererServer::stop() {
  jack_timer_.stop();
  refresh_timer_.stop();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    early_running_ = false;
  }
  early_wake_.notify_one();
  if (early_thread_.joinable()) early_thread_.join();
  listener_timer_.stop();
  marker_timer_.stop();
  running_ = false;
  if (audio_thread_.joinable()) audio_thread_.join();
}

void BinauralRendererServer::note(const std::string& message, bool warning) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    counters_.last_message = message;
  }
  if (warning) {
    ROS_WARN("binaural_renderer: %s", message.c_str());
  } else {
    ROS_INFO("binaural_renderer: %s", message.c_str());
  }
}

void BinauralRendererServer::offerRoom(StreamRoom room, std::optional<std::uint64_t> rsao_generation) {
  // The transforms of a room change (some 11 ms for a 2 s third-order response) run here,
  // on the caller's thread, and check its order; the audio thread swaps it in.
  try {
    room.prepared = stream_->prepareRoom(room.ambix);
    if (room.simulated_walk) room.prepared_early = stream_->prepareEarlyResponse(room.early);
  } catch (const core::InputError& e) {
    rejectRoom(e.what());
    return;
  }
  auto shared = std::make_shared<const StreamRoom>(std::move(room));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (rsao_generation && *rsao_generation != rsao_generation_) return;
    pending_room_ = shared;
  }
  for (const std::string& n : shared->notes) note(n, false);
}

void BinauralRendererServer::rejectRoom(const std::string& why) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.rooms_rejected;
  }
  note("room refused, the previous one plays on: " + why, true);
}

void BinauralRendererServer::onSource(const room_reverb::AudioBuffer::ConstPtr& message) {
  try {
    const core::AudioBuffer chunk = fromMessage(*message, NonFiniteSamples::kKeep);
    std::string n;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      n = source_queue_->push(chunk);
    }
    if (!n.empty()) note(n, false);
  } catch (const std::exception& e) {
    note(std::string("a ~source chunk was ignored: ") + e.what(), true);
  }
}

void BinauralRendererServer::onRsao(const room_reverb::Rsao::ConstPtr& message) {
  try {
    offerRsao(fromMessage(*message), "rsao");
  } catch (const std::exception& e) {
    rejectRoom(std::string("~rsao: ") + e.what());
  }
}

void BinauralRendererServer::onImpulseResponse(const room_reverb::ImpulseResponse::ConstPtr& message) {
  try {
    offerRoom(roomFromImpulseResponse(*message));
  } catch (const std::exception& e) {
    rejectRoom(std::string("~impulse_response: ") + e.what());
  }
}

void BinauralRendererServer::onRoomScene(const room_reverb::RoomScene::ConstPtr& message) {
  std::uint64_t generation = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    generation = ++scene_generation_;
    last_scene_ = message;
  }
  playScene(*message, generation);
}

void BinauralRendererServer::onHeadOrientation(const geometry_msgs::QuaternionStamped::ConstPtr& message) {
  const auto& q = message->quaternion;
  try {
    const Eigen::Quaterniond head = core::validatedRotation(Eigen::Quaterniond(q.w, q.x, q.y, q.z));
    std::lock_guard<std::mutex> lock(mutex_);
    pending_head_ = head;
    last_head_ = head;
  } catch (const std::exception& e) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++counters_.orientations_rejected;
    }
    ROS_WARN_THROTTLE(5.0, "binaural_renderer: a head orientation was ignored: %s", e.what());
  }
}

}  // namespace room_reverb::ros_bridge
