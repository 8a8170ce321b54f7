// The binaural_renderer's six degrees of freedom: the room model an RSAO is walked in
// (~room_model with TF room -> rig, or ~room_model_file), the listener's pose
// (~listener_pose), and on the audio thread the early reflections as taps moved to the
// listener block by block (listener_translation.h, reflection_tap_bank.h).
#include <algorithm>

#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/binaural/reflection_tap_bank.h"
#include "room_reverb/binaural/walk_render.h"
#include "room_reverb/common/error.h"
#include "room_reverb/ros/binaural_renderer_server.h"
#include "room_reverb/ros/listener_markers.h"
#include "room_reverb/ros/room_conversions.h"
#include "room_reverb/ros/room_markers.h"

namespace room_reverb::ros_bridge {
namespace {

// A listener outside the room model's box is moved this far inside it.
constexpr double kClampMarginM = 0.05;
// Taps read up to this far back: the early part ends at the mixing time (tens of ms), and
// a listener may walk a few metres further from the source than the microphone stood.
constexpr double kMaxTapDelayS = 1.0;

}  // namespace

void BinauralRendererServer::offerRsao(const core::Rsao& rsao, const std::string& what) {
  std::shared_ptr<const core::RoomModel> walkable;
  std::uint64_t generation = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_rsao_ = std::make_pair(rsao, what);
    walkable = walkable_room_;
    generation = ++rsao_generation_;
  }
  try {
    offerRoom(roomFromRsao(rsao, rsao_seed_, what, walkable), generation);
  } catch (const core::InputError& e) {
    if (!walkable) throw;
    // An RSAO the room model cannot place (its source outside the box, say) still plays,
    // at the capture point.
    note(what + " cannot be walked in the room model (" + e.what() + "); it plays as measured", true);
    offerRoom(roomFromRsao(rsao, rsao_seed_, what), generation);
  }
}

void BinauralRendererServer::onRoomModel(const room_reverb::RoomModel::ConstPtr& message) {
  try {
    core::RoomModel model = fromMessage(*message);
    const geometry_msgs::TransformStamped rig =
        tf_buffer_->lookupTransform(room_frame_, rig_frame_, ::ros::Time(0), ::ros::Duration(2.0));
    const auto& t = rig.transform.translation;
    const auto& r = rig.transform.rotation;
    model.rig_position_m = Eigen::Vector3d(t.x, t.y, t.z);
    model.rig_rotation = core::validatedRotation(Eigen::Quaterniond(r.w, r.x, r.y, r.z));
    std::optional<std::pair<core::Rsao, std::string>> rsao;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      walkable_room_ = std::make_shared<const core::RoomModel>(std::move(model));
      rsao = last_rsao_;
    }
    note("~room_model: RSAO rooms are walkable in a " + std::to_string(message->size.x) + " x " +
             std::to_string(message->size.y) + " x " + std::to_string(message->size.z) + " m room",
         false);
    if (rsao) offerRsao(rsao->first, rsao->second);
  } catch (const std::exception& e) {
    note(std::string("~room_model ignored: ") + e.what(), true);
  }
}

void BinauralRendererServer::onListenerPose(const geometry_msgs::PoseStamped::ConstPtr& message) {
  const auto& p = message->pose.position;
  const auto& q = message->pose.orientation;
  acceptListenerPose(Eigen::Vector3d(p.x, p.y, p.z), Eigen::Quaterniond(q.w, q.x, q.y, q.z), "~listener_pose",
                     message->header.stamp);
}

void BinauralRendererServer::acceptListenerPose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation,
                                                const char* from, const ::ros::Time& stamp) {
  try {
    if (!position.allFinite()) throw core::InputError("the position is not finite");
    const Eigen::Quaterniond head = core::validatedRotation(orientation);
    // When the pose was taken: its stamp, unless it has none or one ahead of this clock
    // (another clock's), then now.
    const double now_s = ::ros::Time::now().toSec();
    const double pose_s = !stamp.isZero() && stamp.toSec() <= now_s ? stamp.toSec() : now_s;
    std::lock_guard<std::mutex> lock(mutex_);
    pending_head_ = head;
    pending_position_ = position;
    // The oldest movement not yet heard: a newer pose supersedes it, but is heard no sooner.
    if (!pending_pose_s_) pending_pose_s_ = pose_s;
    last_listener_position_ = position;
    last_head_ = head;
    early_wake_.notify_one();
  } catch (const std::exception& e) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++counters_.orientations_rejected;
    }
    ROS_WARN_THROTTLE(5.0, "binaural_renderer: a listener pose from %s was ignored: %s", from, e.what());
  }
}

void BinauralRendererServer::followListenerFrame() {
  geometry_msgs::TransformStamped head;
  try {
    head = tf_buffer_->lookupTransform(room_frame_, listener_frame_, ::ros::Time(0));
  } catch (const std::exception& e) {
    // Not published yet, or the tracker stopped: the listener stays where it was.
    ROS_WARN_THROTTLE(10.0, "binaural_renderer: no TF %s -> %s yet: %s", room_frame_.c_str(), listener_frame_.c_str(),
                      e.what());
    return;
  }
  if (head.header.stamp == last_listener_tf_stamp_ && !head.header.stamp.isZero()) return;  // nothing new
  last_listener_tf_stamp_ = head.header.stamp;
  const auto& t = head.transform.translation;
  const auto& r = head.transform.rotation;
  acceptListenerPose(Eigen::Vector3d(t.x, t.y, t.z), Eigen::Quaterniond(r.w, r.x, r.y, r.z), "TF", head.header.stamp);
}

void BinauralRendererServer::publishMarkers() {
  std::shared_ptr<const StreamRoom> room;
  std::optional<Eigen::Vector3d> listener;
  Eigen::Quaterniond head;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    room = current_room_;
    listener = last_listener_position_;
    head = last_head_;
  }
  const ::ros::Time stamp = ::ros::Time::now();
  if (!room || (!room->translation && !room->simulated_walk)) {
    if (markers_shown_) {  // the walkable room stopped playing: take its markers away
      visualization_msgs::MarkerArray clear;
      clear.markers.push_back(baseMarker(room_frame_, stamp, "", 0, visualization_msgs::Marker::SPHERE));
      clear.markers.back().action = visualization_msgs::Marker::DELETEALL;
      marker_publisher_.publish(clear);
      markers_shown_ = false;
    }
    return;
  }
  // The paths cost some image-source work (about a millisecond): only for a viewer.
  if (marker_publisher_.getNumSubscribers() == 0) return;
  const Eigen::Vector3d source = room->translation ? room->translation->sourcePosition()
                                                   : room->simulated_walk->sourcePosition();
  const Eigen::Vector3d at = listener ? *listener
                                      : (room->translation ? room->translation->rigPosition()
                                                           : room->simulated_walk->referenceListener());
  std::vector<DrawnPath> paths;
  try {
    paths = room->translation ? drawnPaths(*room->translation, room->translation->heardPathsAt(at))
                              : drawnPaths(*room->simulated_walk, at);
  } catch (const core::InputError&) {
    // Outside the room or inside an object: the head is drawn where the tracker says, with
    // no paths (the audio thread says why, counted in ~status).
  }
  marker_publisher_.publish(listenerMarkers(source, paths, at, head, room_frame_, stamp));
  markers_shown_ = true;
}

void BinauralRendererServer::takeRoomTaps(const StreamRoom& room) {
  translation_ = room.translation;
  taps_room_model_ = room.room_model;
  if (!translation_) {
    stream_->setEarlyTaps(nullptr);
    return;
  }
  core::ReflectionTapBankOptions options;
  options.order = decoder_.order;
  options.block_size = block_frames_;
  options.max_delay_s = kMaxTapDelayS;
  stream_->setEarlyTaps(std::make_unique<core::ReflectionTapBank>(translation_->reflectionsAtRig(), options));
  // Until a pose arrives the listener stands at the microphone.
  if (!listener_known_) listener_from_ = listener_to_ = translation_->rigPosition();
  walk_targets_.place({});
  if (auto targets = tapTargetsFor(listener_to_)) {
    stream_->earlyTaps()->setTargets(*targets);
    walk_targets_.place(std::move(*targets));
  }
}

std::optional<std::vector<core::TapTarget>> BinauralRendererServer::tapTargetsFor(const Eigen::Vector3d& wanted) {
  if (!translation_) return std::nullopt;
  Eigen::Vector3d listener = wanted;
  if (taps_room_model_) {
    const Eigen::Vector3d low = Eigen::Vector3d::Constant(kClampMarginM);
    const Eigen::Vector3d high = taps_room_model_->size_m - low;
    listener = wanted.cwiseMax(low).cwiseMin(high);
  }
  bool clamped = listener != wanted;
  std::vector<core::TapTarget> targets;
  try {
    targets = core::tapTargetsAt(*translation_, listener);
  } catch (const core::InputError& e) {
    // Inside an object: the taps stay where they were.
    ROS_WARN_THROTTLE(5.0, "binaural_renderer: listener kept where it was: %s", e.what());
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.listener_positions_clamped;
    return std::nullopt;
  }
  if (clamped) {
    ROS_WARN_THROTTLE(5.0, "binaural_renderer: the listener (%.2f, %.2f, %.2f) m is outside the room model; heard at "
                      "its edge", wanted.x(), wanted.y(), wanted.z());
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.listener_positions_clamped;
  }
  return targets;
}

}  // namespace room_reverb::ros_bridge
