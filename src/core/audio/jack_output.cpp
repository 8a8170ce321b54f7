#include "room_reverb/audio/jack_output.h"

#include <jack/jack.h>
#include <jack/ringbuffer.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/stream_resampler.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

struct JackOutput::Client {
  jack_client_t* client = nullptr;
  jack_port_t* ports[2] = {nullptr, nullptr};
  jack_ringbuffer_t* ring = nullptr;  // interleaved float pairs
  std::unique_ptr<StreamResampler> resamplers[2];
  ~Client() {
    if (client != nullptr) {
      jack_deactivate(client);
      jack_client_close(client);
    }
    if (ring != nullptr) jack_ringbuffer_free(ring);
  }
};

// C callbacks into the object (friend: they reach the private process and shutdown).
struct JackCallbacks {
  static int process(jack_nframes_t frames, void* self) {
    return static_cast<JackOutput*>(self)->process(frames);
  }
  static void shutdown(jack_status_t, const char* reason, void* self) {
    static_cast<JackOutput*>(self)->onShutdown(reason != nullptr ? reason : "the server stopped");
  }
};

namespace {

constexpr std::size_t kFrameBytes = 2 * sizeof(float);

// libjack prints its own multi-line complaints (no server socket, and so on) to stderr;
// the constructor's InputError says what matters in one line instead.
void quietJackMessage(const char*) {}

}  // namespace

std::vector<std::string> parseJackConnect(const std::string& connect) {
  if (connect == "physical" || connect.empty()) return {};
  std::vector<std::string> names;
  std::size_t start = 0;
  while (start <= connect.size()) {
    const std::size_t comma = std::min(connect.find(',', start), connect.size());
    std::string name = connect.substr(start, comma - start);
    name.erase(0, name.find_first_not_of(' '));
    name.erase(name.find_last_not_of(' ') + 1);
    names.push_back(name);
    start = comma + 1;
  }
  if (names.size() != 2 || names[0].empty() || names[1].empty()) {
    throw InputError("JACK output: connect to \"physical\", nothing (\"\") or two ports \"A,B\" (got \"" + connect + "\")");
  }
  return names;
}

JackOutput::JackOutput(const JackOutputOptions& options)
    : client_(std::make_unique<Client>()), stream_rate_hz_(options.stream_rate_hz) {
  if (options.client_name.empty() || options.client_name.size() > static_cast<std::size_t>(jack_client_name_size() - 1)) {
    throw InputError("JACK output: the client name must be 1 to " + std::to_string(jack_client_name_size() - 1) +
                     " characters");
  }
  if (!(options.stream_rate_hz >= kMinSampleRateHz && options.stream_rate_hz <= kMaxSampleRateHz)) {
    throw InputError("JACK output: the stream rate is outside the accepted range");
  }
  if (!(options.ring_seconds >= 0.05 && options.ring_seconds <= 10.0)) {
    throw InputError("JACK output: the ring must hold 0.05 to 10 s");
  }
  parseJackConnect(options.connect);
  jack_set_error_function(quietJackMessage);
  jack_set_info_function(quietJackMessage);
  jack_status_t status{};
  const auto open_options = static_cast<jack_options_t>(
      JackNoStartServer | (options.server_name.empty() ? 0 : JackServerName));
  client_->client = options.server_name.empty()
                        ? jack_client_open(options.client_name.c_str(), open_options, &status)
                        : jack_client_open(options.client_name.c_str(), open_options, &status,
                                           options.server_name.c_str());
  if (client_->client == nullptr) {
    const std::string server = options.server_name.empty() ? "the default JACK server" : "JACK server \"" + options.server_name + "\"";
    if (status & JackServerFailed) {
      throw InputError("JACK output: " + server + " is not running (start one: jackd -d alsa, or jackd -d dummy)");
    }
    std::ostringstream os;
    os << "JACK output: " << server << " refused the client (status 0x" << std::hex << static_cast<int>(status) << ")";
    throw InputError(os.str());
  }
  client_name_ = jack_get_client_name(client_->client);
  server_rate_hz_ = static_cast<double>(jack_get_sample_rate(client_->client));
  if (server_rate_hz_ != stream_rate_hz_) {
    for (auto& resampler : client_->resamplers) {
      resampler = std::make_unique<StreamResampler>(stream_rate_hz_, server_rate_hz_);
    }
  }
  const auto ring_bytes = static_cast<std::size_t>(std::ceil(options.ring_seconds * server_rate_hz_)) * kFrameBytes;
  client_->ring = jack_ringbuffer_create(ring_bytes);
  if (client_->ring == nullptr) throw InputError("JACK output: no memory for the ring buffer");
  jack_ringbuffer_mlock(client_->ring);  // best effort: the process callback must not page-fault
  const char* names[2] = {"out_left", "out_right"};
  for (int c = 0; c < 2; ++c) {
    client_->ports[c] = jack_port_register(client_->client, names[c], JACK_DEFAULT_AUDIO_TYPE, JackPortIsOutput, 0);
    if (client_->ports[c] == nullptr) throw InputError("JACK output: the server refused the port " + std::string(names[c]));
  }
  jack_set_process_callback(client_->client, JackCallbacks::process, this);
  jack_on_info_shutdown(client_->client, JackCallbacks::shutdown, this);
  running_ = true;
  if (jack_activate(client_->client) != 0) throw InputError("JACK output: the server did not activate the client");
  try {
    connectPorts(options.connect);
  } catch (...) {
    close();
    throw;
  }
}

JackOutput::~JackOutput() { close(); }

void JackOutput::close() {
  // The callbacks stop before anything they use goes (unique_ptr::reset clears the pointer
  // before it deletes, and the process callback reads the ports through it).
  if (client_ && client_->client != nullptr) jack_deactivate(client_->client);
  client_.reset();
}

void JackOutput::connectPorts(const std::string& connect) {
  std::vector<std::string> targets;
  if (connect == "physical") {
    const char** ports = jack_get_ports(client_->client, nullptr, JACK_DEFAULT_AUDIO_TYPE,
                                        JackPortIsPhysical | JackPortIsInput);
    if (ports != nullptr) {
      for (int i = 0; ports[i] != nullptr && i < 2; ++i) targets.emplace_back(ports[i]);
      jack_free(ports);
    }
    if (targets.size() == 1) targets.push_back(targets[0]);  // a mono device hears both
  } else if (!connect.empty()) {
    targets = parseJackConnect(connect);
    for (const std::string& name : targets) {
      jack_port_t* port = jack_port_by_name(client_->client, name.c_str());
      if (port == nullptr) throw InputError("JACK output: no port \"" + name + "\" on the server");
      if (!(jack_port_flags(port) & JackPortIsInput)) throw InputError("JACK output: \"" + name + "\" is not an input port");
    }
  }
  for (std::size_t c = 0; c < targets.size(); ++c) {
    const int result = jack_connect(client_->client, jack_port_name(client_->ports[c]), targets[c].c_str());
    if (result != 0 && result != EEXIST) throw InputError("JACK output: could not connect to \"" + targets[c] + "\"");
    connected_to_.push_back(targets[c]);
  }
}

std::size_t JackOutput::periodFrames() const { return jack_get_buffer_size(client_->client); }

std::string JackOutput::portName(int channel) const {
  return client_name_ + (channel == 0 ? ":out_left" : ":out_right");
}

std::string JackOutput::description() const {
  std::ostringstream os;
  os << "JACK client " << client_name_ << " at " << server_rate_hz_ << " Hz, period " << periodFrames() << " frames";
  if (server_rate_hz_ != stream_rate_hz_) os << " (resampled from " << stream_rate_hz_ << " Hz)";
  os << ", ";
  if (connected_to_.empty()) {
    os << "not connected";
  } else {
    os << "playing to " << connected_to_[0] << (connected_to_.size() > 1 ? " and " + connected_to_[1] : "");
  }
  return os.str();
}

int JackOutput::process(std::uint32_t frames) {
  float* out[2] = {static_cast<float*>(jack_port_get_buffer(client_->ports[0], frames)),
                   static_cast<float*>(jack_port_get_buffer(client_->ports[1], frames))};
  const std::size_t available = jack_ringbuffer_read_space(client_->ring) / kFrameBytes;
  const std::size_t take = std::min<std::size_t>(available, frames);
  // The ring holds whole frames and its size is a power of two, so both parts of the
  // read vector hold whole frames too.
  jack_ringbuffer_data_t parts[2];
  jack_ringbuffer_get_read_vector(client_->ring, parts);
  std::size_t n = 0;
  for (const auto& part : parts) {
    const auto* samples = reinterpret_cast<const float*>(part.buf);
    const std::size_t in_part = std::min(part.len / kFrameBytes, take - n);
    for (std::size_t i = 0; i < in_part; ++i, ++n) {
      out[0][n] = samples[2 * i];
      out[1][n] = samples[2 * i + 1];
    }
  }
  jack_ringbuffer_read_advance(client_->ring, take * kFrameBytes);
  std::fill(out[0] + take, out[0] + frames, 0.0f);
  std::fill(out[1] + take, out[1] + frames, 0.0f);
  if (primed_.load(std::memory_order_acquire)) {
    played_frames_.fetch_add(frames, std::memory_order_release);
    if (take < frames) {
      underrun_frames_.fetch_add(frames - take, std::memory_order_relaxed);
      underrun_cycles_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  return 0;
}

void JackOutput::onShutdown(const std::string& reason) {
  {
    std::lock_guard<std::mutex> lock(reason_mutex_);
    shutdown_reason_ = reason;
  }
  running_ = false;
}

std::string JackOutput::shutdownReason() const {
  std::lock_guard<std::mutex> lock(reason_mutex_);
  return shutdown_reason_;
}

void JackOutput::write(const float* left, const float* right, std::size_t frames) {
  const float* channels[2] = {left, right};
  std::size_t count = frames;
  if (client_->resamplers[0]) {
    resampled_left_.clear();
    resampled_right_.clear();
    client_->resamplers[0]->process(left, frames, resampled_left_);
    client_->resamplers[1]->process(right, frames, resampled_right_);
    count = std::min(resampled_left_.size(), resampled_right_.size());  // equal: same converter, same input
    channels[0] = resampled_left_.data();
    channels[1] = resampled_right_.data();
  }
  const std::size_t room = jack_ringbuffer_write_space(client_->ring) / kFrameBytes;
  const std::size_t fits = std::min(room, count);
  interleaved_.resize(2 * fits);
  for (std::size_t n = 0; n < fits; ++n) {
    interleaved_[2 * n] = channels[0][n];
    interleaved_[2 * n + 1] = channels[1][n];
  }
  jack_ringbuffer_write(client_->ring, reinterpret_cast<const char*>(interleaved_.data()), fits * kFrameBytes);
  if (fits < count) overflow_frames_ += count - fits;
  primed_.store(true, std::memory_order_release);
}

double JackOutput::playedStreamFrames() const {
  return static_cast<double>(played_frames_.load(std::memory_order_acquire)) * stream_rate_hz_ / server_rate_hz_;
}

double JackOutput::queuedStreamFrames() const {
  return static_cast<double>(jack_ringbuffer_read_space(client_->ring) / kFrameBytes) * stream_rate_hz_ / server_rate_hz_;
}

JackOutputCounters JackOutput::counters() const {
  JackOutputCounters c;
  c.played_frames = played_frames_.load();
  c.underrun_frames = underrun_frames_.load();
  c.underrun_cycles = underrun_cycles_.load();
  c.overflow_frames = overflow_frames_.load();
  return c;
}

}  // namespace room_reverb::core
