// The binaural_renderer's JACK output (~jack_output): a ROS timer joins the JACK server
// (and joins it again after it went away) off the audio thread, which takes the client
// over, paces the stream by the sound card's clock while it plays, and writes every chunk
// it publishes to it as well.
#include "room_reverb/common/error.h"
#include "room_reverb/ros/binaural_renderer_server.h"
#include "room_reverb/ros/parameters.h"

namespace room_reverb::ros_bridge {

void BinauralRendererServer::setUpJack(::ros::NodeHandle& private_nh) {
  bool enabled = false;
  typedParam(private_nh, "jack_output", enabled, false);
  typedParam(private_nh, "jack_client_name", jack_options_.client_name, std::string("binaural_renderer"));
  typedParam(private_nh, "jack_server", jack_options_.server_name, std::string(""));
  typedParam(private_nh, "jack_connect", jack_options_.connect, std::string("physical"));
  double retry_s = 2.0;
  typedParam(private_nh, "jack_retry_s", retry_s, 2.0);
  if (!(retry_s >= 0.1 && retry_s <= 3600.0)) throw core::InputError("parameter ~jack_retry_s must be 0.1 to 3600 s");
  jack_options_.stream_rate_hz = core::kInternalSampleRateHz;
  if (!enabled) {
    jack_state_ = "off";
    return;
  }
  // Options the server cannot be blamed for stop the node now, as any bad parameter does.
  if (jack_options_.client_name.empty()) throw core::InputError("parameter ~jack_client_name must not be empty");
  try {
    core::parseJackConnect(jack_options_.connect);
  } catch (const core::InputError& e) {
    throw core::InputError(std::string("parameter ~jack_connect: ") + e.what());
  }
  jack_state_ = "waiting for the JACK server";
  joinJack();
  jack_timer_ = private_nh.createWallTimer(::ros::WallDuration(retry_s), [this](const ::ros::WallTimerEvent&) { joinJack(); });
}

void BinauralRendererServer::joinJack() {
  std::shared_ptr<core::JackOutput> retired;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    retired.swap(retired_jack_);
  }
  retired.reset();  // closed here: jack_client_close may wait on a server that is going away
  if (jack_playing_.load()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_jack_) return;  // the audio thread has not taken the last one yet
  }
  try {
    auto output = std::make_shared<core::JackOutput>(jack_options_);
    note("JACK output: " + output->description(), false);
    std::lock_guard<std::mutex> lock(mutex_);
    pending_jack_ = std::move(output);
  } catch (const core::InputError& e) {
    std::string why = e.what();
    const std::string prefix = "JACK output: ";
    if (why.rfind(prefix, 0) == 0) why.erase(0, prefix.size());
    bool changed = false;
    std::string state;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      state = "waiting for the JACK server" + (jack_lost_.empty() ? "" : " (it went away: " + jack_lost_ + ")") + ": " + why;
      changed = state != jack_state_;
      jack_state_ = state;
    }
    if (changed) note(state, true);  // once per distinct reason, not every retry
  }
}

void BinauralRendererServer::takeJack() {
  if (jack_ && !jack_->serverRunning()) {
    const std::string why = jack_->shutdownReason();
    const core::JackOutputCounters c = jack_->counters();
    jack_counts_before_.underrun_frames += c.underrun_frames;
    jack_counts_before_.overflow_frames += c.overflow_frames;
    jack_playing_ = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      retired_jack_ = std::move(jack_);
      jack_lost_ = why;
      jack_state_ = "waiting for the JACK server (it went away: " + why + ")";
    }
    note("JACK output: the server went away (" + why + "); the stream goes on by ROS time", true);
  }
  std::shared_ptr<core::JackOutput> offered;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    offered.swap(pending_jack_);
    if (offered) {
      jack_state_ = offered->description();
      jack_lost_.clear();
    }
  }
  if (!offered) return;
  jack_ = std::move(offered);
  jack_playing_ = true;
  // The card's clock continues the stream's timeline from the chunk due next. The ring
  // starts with a period and a chunk of silence: the card takes a period at a time, and
  // the chunk's margin covers the wake-up and the render.
  jack_epoch_s_ = pacer_->started() ? pacer_->dueTime(pacer_->chunkIndex()) : ::ros::Time::now().toSec();
  const double lead = static_cast<double>(jack_->periodFrames()) * core::kInternalSampleRateHz / jack_->serverRateHz() +
                      static_cast<double>(block_frames_ * chunk_blocks_);
  const std::vector<float> silence(static_cast<std::size_t>(lead), 0.0f);
  jack_->write(silence.data(), silence.data(), silence.size());
}

double BinauralRendererServer::streamClock() const {
  if (!jack_) return ::ros::Time::now().toSec();
  return jack_epoch_s_ + jack_->playedStreamFrames() / core::kInternalSampleRateHz;
}

}  // namespace room_reverb::ros_bridge
