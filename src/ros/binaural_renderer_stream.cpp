// The binaural_renderer's audio thread (pacing, rendering, publishing, status) and its
// ~render_to_file service; the rest of the node is in binaural_renderer_server.cpp.
#include <room_reverb/StreamStatus.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/audio/channel_mix.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/binaural/walk_render.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/realtime_thread.h"
#include "room_reverb/ros/binaural_renderer_server.h"

namespace room_reverb::ros_bridge {
namespace {

double cpuSeconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

void BinauralRendererServer::audioLoop() {
  const double chunk_period_s = pacer_options_.chunk_period_s;
  const auto status_period_chunks = std::max<std::uint64_t>(1, std::llround(status_period_s_ / chunk_period_s));
  const core::ThreadScheduling scheduling = core::requestRealtimeScheduling(realtime_priority_);
  audio_scheduling_ = scheduling.description;
  if (realtime_priority_ > 0 && !scheduling.realtime) {
    ROS_WARN("binaural_renderer: audio thread at %s; under load chunks may be dropped", scheduling.description.c_str());
  } else {
    ROS_INFO("binaural_renderer: audio thread at %s", scheduling.description.c_str());
  }
  cpu_thread_mark_ = cpuSeconds(CLOCK_THREAD_CPUTIME_ID);
  cpu_process_mark_ = cpuSeconds(CLOCK_PROCESS_CPUTIME_ID);
  while (running_ && ::ros::ok()) {
    takeJack();
    const double now = streamClock();
    const core::StreamPacer::Step step = pacer_->next(now);
    if (step.kind == core::StreamPacer::Step::kWait) {
      // On the wall clock, sleep until the chunk is due (at most 50 ms, to notice shutdown).
      // Under simulated time the clock may stop, jump or run at another rate: poll it in
      // 2 ms wall-clock steps. The card's clock advances a period at a time: poll it in
      // 5 ms steps at most.
      const double cap_s = jack_ ? 0.005 : ::ros::Time::isSimTime() ? 0.002 : 0.05;
      const double wait_s = std::clamp(step.until - now, 0.0001, cap_s);
      ::ros::WallDuration(wait_s).sleep();
      continue;
    }
    if (step.dropped > 0) {
      const std::size_t frames = static_cast<std::size_t>(step.dropped) * block_frames_ * chunk_blocks_;
      if (looped_source_) {
        looped_source_->skip(frames);
      } else {
        std::lock_guard<std::mutex> lock(mutex_);
        source_queue_->skip(frames);
      }
      ROS_WARN_THROTTLE(5.0, "binaural_renderer: %llu chunk(s) dropped: the renderer fell more than %.3f s behind",
                        static_cast<unsigned long long>(step.dropped), pacer_options_.max_lag_s);
    }
    const double cpu_before = cpuSeconds(CLOCK_THREAD_CPUTIME_ID);
    renderChunk();
    worst_chunk_s_ = std::max(worst_chunk_s_, cpuSeconds(CLOCK_THREAD_CPUTIME_ID) - cpu_before);
    const std::uint64_t index = pacer_->chunkIndex();
    const ::ros::Time stream_start(pacer_->startTime());
    chunk_message_.header.stamp = stream_start + ::ros::Duration(static_cast<double>(index) * chunk_period_s);
    if (taken_pose_s_) {
      // Its first sample reaches the listener at its due time, the chunk's stamp (StreamPacer).
      worst_pose_to_ear_s_ = std::max(worst_pose_to_ear_s_, chunk_message_.header.stamp.toSec() - *taken_pose_s_);
    }
    if (jack_) jack_->write(left_.data(), right_.data(), left_.size());
    binaural_publisher_.publish(chunk_message_);
    const std::uint64_t late_before = pacer_->counters().late;
    pacer_->published(streamClock());
    if (pacer_->counters().late > late_before) {
      ROS_WARN_THROTTLE(5.0, "binaural_renderer: chunk %llu was published late",
                        static_cast<unsigned long long>(index));
    }
    // A status after the first chunk, then every status_period_s of stream published.
    const std::uint64_t published = pacer_->counters().published;
    if (published == 1 || published >= chunks_at_mark_ + status_period_chunks) publishStatus();
  }
}

void BinauralRendererServer::renderChunk() {
  std::shared_ptr<const StreamRoom> room;
  std::optional<Eigen::Quaterniond> head;
  std::optional<Eigen::Vector3d> position;
  std::shared_ptr<const PendingEarly> early;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    room.swap(pending_room_);
    head.swap(pending_head_);
    position.swap(pending_position_);
    taken_pose_s_ = std::exchange(pending_pose_s_, std::nullopt);
    early.swap(pending_early_);
  }
  if (position) {
    listener_to_ = *position;
    if (!listener_known_) listener_from_ = listener_to_;
    listener_known_ = true;
  }
  if (room) {
    try {
      const std::string warning = stream_->setRoom(room->prepared);
      takeRoomTaps(*room);
      // A walkable simulated room brings its image-source part; any other room takes the
      // last one away.
      if (room->simulated_walk) {
        stream_->setEarlyResponse(room->prepared_early);
      } else if (early_walk_) {
        stream_->setEarlyResponse(no_early_);
      }
      early_walk_ = room->simulated_walk;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        current_room_ = room;
        ++counters_.room_changes;
      }
      early_wake_.notify_one();
      note("now playing " + room->description + (warning.empty() ? "" : "; " + warning), !warning.empty());
    } catch (const std::exception& e) {
      rejectRoom(e.what());
    }
  }
  if (head) stream_->setHeadOrientation(*head);
  // The worker's image-source part for where the listener is now, if it belongs to the
  // room playing.
  if (early && early->walk == early_walk_ && early_walk_) stream_->setEarlyResponse(early->early);

  // A walking listener: the taps' targets where the listener is at the end of this chunk
  // (one tapTargetsAt a chunk), blended per block from where the
  // last chunk left them.
  core::ReflectionTapBank* taps = stream_->earlyTaps();
  bool walking = false;
  if (translation_ && taps && listener_from_ != listener_to_) {
    if (auto targets = tapTargetsFor(listener_to_)) {
      walk_targets_.beginChunk(std::move(*targets), chunk_blocks_);
      walking = true;
    }
  }
  for (std::size_t b = 0; b < chunk_blocks_; ++b) {
    if (looped_source_) {
      looped_source_->read(source_block_.data(), block_frames_);
    } else {
      std::lock_guard<std::mutex> lock(mutex_);
      source_queue_->read(source_block_.data(), block_frames_);
    }
    // The taps move to where the listener is at the end of this block, on the way from
    // the last chunk's position to the newest.
    if (walking) taps->setTargets(walk_targets_.atBlock(b));
    stream_->process(source_block_.data(), left_.data() + b * block_frames_, right_.data() + b * block_frames_);
  }
  listener_from_ = listener_to_;
  if (walking) walk_targets_.endChunk();
  chunk_message_.header.frame_id = frame_id_;
  chunk_message_.sample_rate_hz = core::kInternalSampleRateHz;
  chunk_message_.channel_count = 2;
  chunk_message_.channel_layout = "binaural";
  chunk_message_.samples.resize(2 * left_.size());
  for (std::size_t n = 0; n < left_.size(); ++n) {
    chunk_message_.samples[2 * n] = left_[n];
    chunk_message_.samples[2 * n + 1] = right_[n];
  }
}

void BinauralRendererServer::publishStatus() {
  room_reverb::StreamStatus status;
  status.header.stamp = ::ros::Time::now();
  status.stream_start = ::ros::Time(pacer_->startTime());
  status.sample_rate_hz = core::kInternalSampleRateHz;
  status.chunk_frames = static_cast<std::uint32_t>(block_frames_ * chunk_blocks_);
  status.block_frames = static_cast<std::uint32_t>(block_frames_);
  const core::StreamPacerCounters& pacing = pacer_->counters();
  status.chunks_published = pacing.published;
  status.chunks_late = pacing.late;
  status.chunks_dropped = pacing.dropped;
  status.clock_restarts = pacing.restarts;
  status.source = source_description_;
  status.audio_scheduling = audio_scheduling_;
  status.walkable = translation_ != nullptr || early_walk_ != nullptr;
  status.listener_position.x = listener_to_.x();
  status.listener_position.y = listener_to_.y();
  status.listener_position.z = listener_to_.z();
  status.non_finite_samples = stream_->nonFiniteSamples();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (source_queue_) {
      status.source_underrun_samples = source_queue_->counters().underrun_samples;
      status.source_overflow_samples = source_queue_->counters().overflow_samples;
      status.non_finite_samples += source_queue_->counters().non_finite_samples;
    }
    if (current_room_) {
      status.room = current_room_->description;
      status.room_duration_s = current_room_->ambix.durationS();
    }
    status.room_changes = counters_.room_changes;
    status.rooms_rejected = counters_.rooms_rejected;
    status.orientations_rejected = counters_.orientations_rejected;
    status.listener_positions_clamped = counters_.listener_positions_clamped;
    status.last_message = counters_.last_message;
    status.jack_output = jack_state_;
  }
  status.jack_underrun_frames = jack_counts_before_.underrun_frames;
  status.jack_overflow_frames = jack_counts_before_.overflow_frames;
  if (jack_) {
    status.jack_underrun_frames += jack_->counters().underrun_frames;
    status.jack_overflow_frames += jack_->counters().overflow_frames;
  }
  // Processor time over stream time since the last status.
  const double thread_cpu = cpuSeconds(CLOCK_THREAD_CPUTIME_ID);
  const double process_cpu = cpuSeconds(CLOCK_PROCESS_CPUTIME_ID);
  const double stream_s = static_cast<double>(pacing.published - chunks_at_mark_) * pacer_options_.chunk_period_s;
  if (stream_s > 0.0) {
    status.render_cpu_share = (thread_cpu - cpu_thread_mark_) / stream_s;
    status.process_cpu_share = (process_cpu - cpu_process_mark_) / stream_s;
  }
  status.worst_chunk_render_s = worst_chunk_s_;
  status.pose_to_ear_s = worst_pose_to_ear_s_;
  cpu_thread_mark_ = thread_cpu;
  cpu_process_mark_ = process_cpu;
  chunks_at_mark_ = pacing.published;
  worst_chunk_s_ = 0.0;
  worst_pose_to_ear_s_ = 0.0;
  status_publisher_.publish(status);
}

bool BinauralRendererServer::renderToFile(room_reverb::RenderToFile::Request& request,
                                          room_reverb::RenderToFile::Response& response) {
  try {
    if (request.source_file.empty()) throw core::InputError("source_file is required");
    if (request.output_file.empty()) throw core::InputError("output_file is required");
    const int rooms = int(!request.bformat_rir_file.empty()) + int(!request.ambisonic_rir_file.empty()) +
                      int(!request.rsao_file.empty()) + int(request.current_room);
    if (rooms != 1) {
      throw core::InputError("give exactly one room: bformat_rir_file (with format), ambisonic_rir_file, rsao_file "
                             "or current_room (got " + std::to_string(rooms) + ")");
    }
    const auto& q = request.head_orientation;
    const bool all_zero = q.x == 0.0 && q.y == 0.0 && q.z == 0.0 && q.w == 0.0;
    const Eigen::Quaterniond head =
        all_zero ? Eigen::Quaterniond::Identity() : core::validatedRotation(Eigen::Quaterniond(q.w, q.x, q.y, q.z));

    std::shared_ptr<const StreamRoom> room;
    std::optional<Eigen::Vector3d> listener;
    if (request.current_room) {
      std::lock_guard<std::mutex> lock(mutex_);
      room = current_room_;
      if (!room) throw core::InputError("current_room: the stream has no room yet");
      listener = last_listener_position_;
    } else if (!request.bformat_rir_file.empty()) {
      if (request.format != "fuma" && request.format != "ambix") {
        throw core::InputError("format must be \"fuma\" or \"ambix\" with bformat_rir_file");
      }
      room = std::make_shared<const StreamRoom>(roomFromFile(request.bformat_rir_file, request.format, rsao_seed_));
      if (room->ambix.channelCount() != 4) throw core::InputError("bformat_rir_file: a first-order B-format RIR has 4 channels");
    } else if (!request.ambisonic_rir_file.empty()) {
      room = std::make_shared<const StreamRoom>(roomFromFile(request.ambisonic_rir_file, "ambix", rsao_seed_));
    } else {
      room = std::make_shared<const StreamRoom>(roomFromFile(request.rsao_file, "rsao", rsao_seed_));
    }
    if (room->simulated_walk) {
      // A walkable simulated room: its image sources where the listener stands now (where
      // it was simulated until a pose arrives) over its late part.
      const core::SimulatedWalk& walk = *room->simulated_walk;
      StreamRoom heard = *room;
      heard.ambix = walk.responseAt(listener ? *listener : walk.referenceListener());
      heard.description += listener ? ", heard where the listener stands" : "";
      room = std::make_shared<const StreamRoom>(std::move(heard));
    } else if (room->translation) {
      // A walkable room: the RSAO as heard where the listener stands now (the microphone
      // until a pose arrives), resynthesised whole.
      const Eigen::Vector3d at = listener ? *listener : room->translation->rigPosition();
      char where[96];
      std::snprintf(where, sizeof where, " heard at (%.2f, %.2f, %.2f) m", at.x(), at.y(), at.z());
      room = std::make_shared<const StreamRoom>(
          roomFromRsao(room->translation->at(at), rsao_seed_, room->description + where));
    }
    const core::AudioBuffer source = core::toInternalRate(core::mixToMono(core::readAudioFile(request.source_file)));
    // As the stream plays it: a mixed-order room cut as ~mixed_order_late says.
    const core::AudioBuffer heard = core::roomResponseAsStreamed(room->ambix, decoder_, stream_->options());
    const core::BinauralRender render = core::convolveBinaural(source, core::binauralRoomResponse(heard, decoder_, head));
    core::writeAudioFile(request.output_file, render.audio, core::SampleEncoding::kFloat32);
    response.success = true;
    response.message = "rendered " + room->description;
    response.duration_s = render.audio.durationS();
    response.peak_dbfs = render.peak_dbfs;
    response.gain_db = render.gain_db;
  } catch (const std::exception& e) {
    response = room_reverb::RenderToFile::Response();
    response.success = false;
    response.message = e.what();
  }
  return true;
}

}  // namespace room_reverb::ros_bridge
