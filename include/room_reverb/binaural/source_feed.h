#pragma once
// The dry source of the streaming renderer, block by block at 48 kHz: a file played in a
// loop, or chunks arriving from a topic.
//
// A topic delivers chunks with jitter, so the queue plays nothing until `prebuffer_s` of
// audio has arrived (a jitter buffer), then plays one block per call. When it runs dry the
// missing samples are zeros, counted as underrun, and it waits for the prebuffer again;
// when more than `max_queued_s` piles up (the publisher runs faster than real time) the
// oldest samples are discarded, counted as overflow. Neither class is thread-safe: the
// renderer guards the queue with its own lock.
#include <cstddef>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/stream_resampler.h"

namespace room_reverb::core {

class LoopedSource {
 public:
  // Any rate and channel count: mixed to mono and resampled to 48 kHz. InputError for an
  // empty or invalid buffer (validateAudioBuffer).
  explicit LoopedSource(const AudioBuffer& source);
  // The next `count` samples, wrapping from the end to the start.
  void read(float* out, std::size_t count);
  // Moves on by `count` samples without reading them (blocks dropped by a late renderer).
  void skip(std::size_t count);
  std::size_t length() const { return samples_.size(); }
  std::size_t position() const { return position_; }

 private:
  std::vector<float> samples_;
  std::size_t position_ = 0;
};

struct SourceQueueCounters {
  std::size_t underrun_samples = 0;    // played as zeros because the queue was empty
  std::size_t overflow_samples = 0;    // discarded because more than max_queued_s was waiting
  std::size_t non_finite_samples = 0;  // NaN or infinite samples, replaced by zeros
  std::size_t resampled_chunks = 0;    // chunks not at 48 kHz, converted
};

class SourceQueue {
 public:
  // InputError unless 0 <= prebuffer_s < max_queued_s.
  SourceQueue(double prebuffer_s, double max_queued_s);
  ~SourceQueue();

  // Appends a chunk of any channel count (mixed to mono) and rate in the project's range
  // (resampled to 48 kHz by a converter kept across chunks; a change of rate starts a new
  // converter). Non-finite samples become zeros, counted. Returns a note for the log when
  // the chunk's rate differs from the previous chunk's ("" otherwise). InputError for a
  // chunk with no channels, unequal channels or a rate outside the range.
  std::string push(const AudioBuffer& chunk);

  // The next `count` samples (see above).
  void read(float* out, std::size_t count);
  // Discards `count` samples as if read (blocks dropped by a late renderer).
  void skip(std::size_t count);

  std::size_t queuedSamples() const { return queue_.size(); }
  bool playing() const { return playing_; }
  const SourceQueueCounters& counters() const { return counters_; }

 private:
  std::size_t prebuffer_;
  std::size_t max_queued_;
  std::deque<float> queue_;
  bool playing_ = false;
  std::unique_ptr<StreamResampler> resampler_;
  double last_rate_hz_ = 0.0;
  std::vector<float> scratch_;
  SourceQueueCounters counters_;
};

}  // namespace room_reverb::core
