#pragma once
// When the streaming renderer publishes each chunk, and which chunks were late or dropped.
// Pure bookkeeping on times in seconds of whatever clock the caller uses (ROS time: the
// wall clock live, /clock during a bag replay), so it is tested without a clock.
//
// Chunk k holds stream frames [kC, (k+1)C) and is due at start + k T (T = C / 48 kHz):
// the time its first sample should reach the listener. The renderer waits until the due
// time, renders and publishes; a chunk published more than `late_tolerance_s` after it was
// due is late (a listener's jitter buffer of that size would have run dry). When the
// renderer has fallen more than `max_lag_s` behind, it does not try to catch up by
// rendering faster than real time: the chunks whose time has passed are dropped (counted;
// the source moves on by as many samples, so it stays in time), and it resumes with the
// chunk due now. A clock that jumps back (a bag replayed from its start again) restarts
// the stream's timeline at the new time.
#include <cstddef>
#include <cstdint>

namespace room_reverb::core {

struct StreamPacerOptions {
  double chunk_period_s = 256.0 / 48000.0;
  double late_tolerance_s = 256.0 / 48000.0;  // default: one chunk
  double max_lag_s = 0.25;
};

struct StreamPacerCounters {
  std::uint64_t published = 0;
  std::uint64_t late = 0;
  std::uint64_t dropped = 0;
  std::uint64_t restarts = 0;  // the clock jumped back
};

class StreamPacer {
 public:
  // InputError unless chunk_period_s > 0, late_tolerance_s >= 0, max_lag_s >= late_tolerance_s.
  explicit StreamPacer(const StreamPacerOptions& options);

  struct Step {
    enum Kind { kWait, kRender } kind = kWait;
    double until = 0.0;           // kWait: sleep until this time
    std::uint64_t dropped = 0;    // kRender: chunks skipped just now (advance the source by as many)
  };

  // What to do at time `now`. The first call starts the timeline at `now` (a time <= 0,
  // a simulated clock not yet running, is waited out).
  Step next(double now);
  // The chunk last returned as kRender was published at `now`.
  void published(double now);

  bool started() const { return started_; }
  double startTime() const { return start_; }
  std::uint64_t chunkIndex() const { return index_; }      // the next chunk to render
  double dueTime(std::uint64_t chunk) const { return start_ + static_cast<double>(chunk) * options_.chunk_period_s; }
  const StreamPacerCounters& counters() const { return counters_; }

 private:
  StreamPacerOptions options_;
  bool started_ = false;
  double start_ = 0.0;
  double last_now_ = 0.0;
  std::uint64_t index_ = 0;
  StreamPacerCounters counters_;
};

}  // namespace room_reverb::core
