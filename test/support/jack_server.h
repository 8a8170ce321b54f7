#pragma once
// A JACK server with the dummy backend (no sound card), started by a test as a user
// starts one (jackd -d dummy), and a JACK client that records what reaches its two input
// ports: the listener's side of a JACK output.
#include <atomic>
#include <cstddef>
#include <memory>
#include <string>
#include <sys/types.h>
#include <vector>

namespace room_reverb::test {

class DummyJackServer {
 public:
  // Starts `jackd --port-max 32 -n NAME -d dummy -r RATE -p PERIOD` (real-time scheduling
  // where the system allows it, as jackd does by default; 32 ports keep its shared memory
  // at some 40 MB instead of 110; NAME "" is a name private to this process) and waits (at
  // most 10 s) until a client can join; the test fails with jackd's log otherwise (ok() is
  // false then).
  explicit DummyJackServer(double rate_hz = 48000.0, std::size_t period_frames = 256, const std::string& name = "");
  ~DummyJackServer();
  DummyJackServer(const DummyJackServer&) = delete;
  DummyJackServer& operator=(const DummyJackServer&) = delete;

  bool ok() const { return ok_; }
  const std::string& name() const { return name_; }
  void stop();  // stops the server now (SIGTERM, as a user does): its clients see it go

 private:
  std::string name_;
  pid_t pid_ = -1;
  bool ok_ = false;
};

// A client with ports in_left and in_right that keeps every frame it is given, up to
// `capacity_frames` (the rest is counted, not kept).
class JackRecorder {
 public:
  JackRecorder(const std::string& server_name, const std::string& client_name, std::size_t capacity_frames);
  ~JackRecorder();
  JackRecorder(const JackRecorder&) = delete;
  JackRecorder& operator=(const JackRecorder&) = delete;

  bool ok() const { return client_ != nullptr; }
  // Connects `source_port` to in_left (channel 0) or in_right (1); false if JACK refused.
  bool connectFrom(const std::string& source_port, int channel);
  // Starts keeping frames (frames before are ignored).
  void record() { recording_ = true; }
  std::size_t framesRecorded() const { return recorded_.load(); }
  // Cycles the server reported late (xruns) while recording: where the graph skipped or
  // repeated a period, the recording and what was sent need not line up across it.
  int xruns() const { return xruns_.load(); }
  // Copies of what was kept.
  std::vector<float> channel(int c) const;
  std::vector<std::string> connectionsOf(const std::string& port) const;

 private:
  static int process(unsigned frames, void* self);
  static int onXrun(void* self);
  void* client_ = nullptr;
  void* ports_[2] = {nullptr, nullptr};
  std::vector<float> samples_[2];
  std::atomic<std::size_t> recorded_{0};
  std::atomic<bool> recording_{false};
  std::atomic<int> xruns_{0};
};

// Where `needle` starts inside `haystack`, by exact equality of every sample; -1 if
// nowhere: how a test finds a stream's samples in what a JACK client heard.
long findExact(const std::vector<float>& haystack, const std::vector<float>& needle);

}  // namespace room_reverb::test
