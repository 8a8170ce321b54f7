#pragma once
// A stereo stream played through a JACK client (Debian's jackd2), so that a listener with
// headphones on the rig's computer hears what the renderer streams.
//
// The producer (the renderer's audio thread) writes frames into a lock-free ring buffer;
// JACK's process callback reads them into two output ports. The callback never waits for
// a lock, allocates or renders: when the ring is short it plays silence and counts the
// missing frames. The frames JACK has consumed are the sound card's clock: a producer that
// paces by playedStreamFrames() follows the card and never drifts from it, which a
// producer paced by the system clock would (tens of ppm: a chunk every few minutes).
//
// A server at another rate than the stream is served through a streaming resampler
// (libsamplerate, medium sinc) on the producer's side. The client never starts a server.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace room_reverb::core {

struct JackOutputOptions {
  std::string client_name = "room_reverb";
  // The server to join: "" for the default one ($JACK_DEFAULT_SERVER, else "default").
  std::string server_name;
  // Where the two ports are connected: "physical" (the first two physical playback ports,
  // the sound card; one port gets both channels), "" (none: the user connects them), or
  // two port names separated by a comma ("system:playback_3,system:playback_4").
  std::string connect = "physical";
  double stream_rate_hz = 48000.0;
  double ring_seconds = 0.5;  // ring capacity at the server's rate
};

struct JackOutputCounters {
  std::uint64_t played_frames = 0;    // frames JACK has taken since the first write
  std::uint64_t underrun_frames = 0;  // of those, frames the ring did not have (silence)
  std::uint64_t underrun_cycles = 0;  // process cycles with any underrun
  std::uint64_t overflow_frames = 0;  // frames written while the ring was full (dropped)
};

// InputError unless `connect` is "physical", "" or two non-empty port names "A,B"
// (JackOutputOptions::connect); the two names otherwise (none for "physical" and "").
std::vector<std::string> parseJackConnect(const std::string& connect);

class JackOutput {
 public:
  // Opens the client, registers out_left and out_right, activates it and connects the
  // ports. InputError (one line) when no server runs, a named port does not exist, or the
  // options are bad.
  explicit JackOutput(const JackOutputOptions& options);
  ~JackOutput();
  JackOutput(const JackOutput&) = delete;
  JackOutput& operator=(const JackOutput&) = delete;

  double serverRateHz() const { return server_rate_hz_; }
  std::size_t periodFrames() const;  // JACK's buffer size now
  const std::string& clientName() const { return client_name_; }  // as the server named it
  const std::vector<std::string>& connectedTo() const { return connected_to_; }
  std::string portName(int channel) const;  // "client:out_left" (0) or "client:out_right" (1)
  // One line for a status display: server, rate, period, connections.
  std::string description() const;

  // Producer side (one thread). Appends `frames` stereo frames at the stream rate;
  // frames that do not fit are dropped and counted.
  void write(const float* left, const float* right, std::size_t frames);
  // Frames at the stream rate that JACK has consumed since the first write: the card's clock.
  double playedStreamFrames() const;
  // Frames queued in the ring, at the stream rate.
  double queuedStreamFrames() const;
  JackOutputCounters counters() const;
  // False once the server shut down or dropped the client; the reason says why.
  bool serverRunning() const { return running_.load(); }
  std::string shutdownReason() const;

 private:
  struct Client;
  friend struct JackCallbacks;
  int process(std::uint32_t frames);
  void onShutdown(const std::string& reason);
  void connectPorts(const std::string& connect);
  void close();

  std::unique_ptr<Client> client_;
  std::string client_name_;
  double stream_rate_hz_ = 48000.0;
  double server_rate_hz_ = 48000.0;
  std::vector<std::string> connected_to_;
  std::vector<float> interleaved_, resampled_left_, resampled_right_;

  std::atomic<bool> running_{false};
  std::atomic<bool> primed_{false};  // the producer has written: underruns count from here
  std::atomic<std::uint64_t> played_frames_{0}, underrun_frames_{0}, underrun_cycles_{0};
  std::atomic<std::uint64_t> overflow_frames_{0};
  mutable std::mutex reason_mutex_;
  std::string shutdown_reason_;
};

}  // namespace room_reverb::core
