// The binaural_renderer's simulated route in six degrees of freedom: a ~room_scene is
// simulated by the room_simulator with its late part apart (late_part), and played as a
// walkable room (simulated_walk.h). A worker thread computes the image-source part where
// the listener stands (some milliseconds: never on the audio thread), which the audio
// thread crossfades in (BinauralStream::setEarlyResponse); a timer asks the simulator for
// a new late part when the listener has walked far from where it was simulated.
#include <cstdio>

#include "room_reverb/common/error.h"
#include "room_reverb/ros/binaural_renderer_server.h"
#include "room_reverb/ros/parameters.h"

namespace room_reverb::ros_bridge {
namespace {

// The image-source part is computed again when the listener has moved this far: 0.09 ms of
// path. Each new part costs the audio thread about 1 ms to partition
// (bench_binaural_renderer, BM_SimulatedWalkChunk), every 30 ms at a walking pace.
constexpr double kEarlyStepM = 0.03;

}  // namespace

void BinauralRendererServer::setUpSimulatedWalk(::ros::NodeHandle& private_nh) {
  typedParam(private_nh, "walk_room_scenes", walk_room_scenes_, true);
  std::string materials_file;
  typedParam(private_nh, "materials_file", materials_file, std::string(""));
  typedParam(private_nh, "walk_refresh_m", walk_refresh_m_, 2.0);
  if (!(walk_refresh_m_ >= 0.0 && walk_refresh_m_ <= 1000.0)) {
    throw core::InputError("parameter ~walk_refresh_m must be 0 (never) to 1000 m");
  }
  library_ = materials_file.empty() ? core::MaterialLibrary::loadDefault() : core::MaterialLibrary::load(materials_file);
  if (!walk_room_scenes_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    early_running_ = true;
  }
  early_thread_ = std::thread([this] { earlyLoop(); });
  if (walk_refresh_m_ > 0.0) {
    refresh_timer_ = private_nh.createWallTimer(::ros::WallDuration(0.5), [this](const ::ros::WallTimerEvent&) { refreshWalk(); });
  }
}

void BinauralRendererServer::playScene(const room_reverb::RoomScene& scene, std::uint64_t generation) {
  room_reverb::SimulateRoom simulate;
  simulate.request.room = scene.room;
  simulate.request.source = scene.source;
  simulate.request.listener = scene.listener;
  simulate.request.mode = scene.mode;
  simulate.request.ambisonic_order = decoder_.order;
  simulate.request.global_scattering = -1.0;
  simulate.request.late_part = walk_room_scenes_;
  // Nodes of one launch start in any order: give the simulator a few seconds to come up.
  if (!simulator_.waitForExistence(::ros::Duration(5.0)) || !simulator_.call(simulate)) {
    rejectRoom("~room_scene: the simulator service " + simulator_.getService() + " did not answer");
    return;
  }
  if (!simulate.response.success) {
    rejectRoom("~room_scene: the simulator refused the room: " + simulate.response.message);
    return;
  }
  const std::string what = "room_scene " + (scene.mode.empty() ? std::string("default mode") : scene.mode);
  StreamRoom room;
  try {
    if (!walk_room_scenes_) throw core::InputError("walking is off (~walk_room_scenes)");
    room = walkableSimulatedRoom(scene, simulate.response, library_, what);
  } catch (const core::InputError& e) {
    if (walk_room_scenes_) note("~room_scene plays where it was simulated: " + std::string(e.what()), true);
    try {
      room = roomFromImpulseResponse(simulate.response.impulse_response);
      room.description = what + ", " + room.description;
    } catch (const std::exception& bad) {
      rejectRoom(std::string("~room_scene: ") + bad.what());
      return;
    }
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (generation != scene_generation_) return;  // a newer scene is on its way
  }
  offerRoom(std::move(room));
}

void BinauralRendererServer::refreshWalk() {
  std::shared_ptr<const core::SimulatedWalk> walk;
  std::optional<Eigen::Vector3d> position;
  room_reverb::RoomScene::ConstPtr scene;
  std::uint64_t generation = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (current_room_) walk = current_room_->simulated_walk;
    position = last_listener_position_;
    scene = last_scene_;
    generation = scene_generation_;
  }
  if (!walk || !position || !scene || (*position - walk->referenceListener()).norm() < walk_refresh_m_) return;
  try {
    walk->requireListener(*position);  // only from where the listener may stand
  } catch (const core::InputError&) {
    return;
  }
  room_reverb::RoomScene moved = *scene;
  moved.listener.x = position->x();
  moved.listener.y = position->y();
  moved.listener.z = position->z();
  char where[96];
  std::snprintf(where, sizeof where, "a new late part for the listener at (%.2f, %.2f, %.2f) m", position->x(),
                position->y(), position->z());
  note(where, false);
  playScene(moved, generation);
}

void BinauralRendererServer::earlyLoop() {
  std::shared_ptr<const core::SimulatedWalk> done_walk;
  Eigen::Vector3d done_at = Eigen::Vector3d::Constant(1e9);
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    // Asleep until the room changes or the listener has walked a step from where the
    // early part was last computed (acceptListenerPose and the audio thread wake it).
    std::shared_ptr<const core::SimulatedWalk> walk;
    early_wake_.wait(lock, [&] {
      walk = current_room_ ? current_room_->simulated_walk : nullptr;
      return !early_running_ || walk != done_walk ||
             (walk && last_listener_position_ && (*last_listener_position_ - done_at).norm() >= kEarlyStepM);
    });
    if (!early_running_) return;
    if (walk != done_walk) {
      // A new room starts with its early part at the simulated listener position.
      done_walk = walk;
      if (walk) done_at = walk->referenceListener();
      continue;
    }
    const Eigen::Vector3d position = *last_listener_position_;
    lock.unlock();
    std::shared_ptr<const PendingEarly> early;
    bool refused = false;
    try {
      // Transformed here too: the audio thread only swaps it in.
      early = std::make_shared<const PendingEarly>(PendingEarly{walk, stream_->prepareEarlyResponse(walk->earlyAt(position))});
    } catch (const core::InputError&) {
      refused = true;  // outside the room or in an object: the early part stays where it was
    }
    lock.lock();
    if (early) pending_early_ = std::move(early);
    if (refused) ++counters_.listener_positions_clamped;
    done_at = position;
  }
}

}  // namespace room_reverb::ros_bridge
