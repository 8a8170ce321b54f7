#include "room_reverb/binaural/source_feed.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "room_reverb/audio/channel_mix.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

LoopedSource::LoopedSource(const AudioBuffer& source) {
  validateAudioBuffer(source, "the looped source");
  if (source.frameCount() == 0) throw InputError("the looped source has no samples");
  samples_ = toInternalRate(mixToMono(source)).channels[0];
  if (samples_.empty()) throw InputError("the looped source is shorter than one sample at 48 kHz");
}

void LoopedSource::read(float* out, std::size_t count) {
  while (count > 0) {
    const std::size_t n = std::min(count, samples_.size() - position_);
    std::copy_n(samples_.begin() + static_cast<std::ptrdiff_t>(position_), n, out);
    out += n;
    count -= n;
    position_ = (position_ + n) % samples_.size();
  }
}

void LoopedSource::skip(std::size_t count) { position_ = (position_ + count) % samples_.size(); }

SourceQueue::SourceQueue(double prebuffer_s, double max_queued_s) {
  if (!(prebuffer_s >= 0.0 && max_queued_s > prebuffer_s && std::isfinite(max_queued_s))) {
    throw InputError("source queue: need 0 <= prebuffer_s < max_queued_s");
  }
  prebuffer_ = static_cast<std::size_t>(std::lround(prebuffer_s * kInternalSampleRateHz));
  max_queued_ = static_cast<std::size_t>(std::lround(max_queued_s * kInternalSampleRateHz));
}

SourceQueue::~SourceQueue() = default;

std::string SourceQueue::push(const AudioBuffer& chunk) {
  if (chunk.channels.empty()) throw InputError("source chunk: no channels");
  for (const auto& channel : chunk.channels) {
    if (channel.size() != chunk.frameCount()) throw InputError("source chunk: channels of different lengths");
  }
  if (!(chunk.sample_rate_hz >= kMinSampleRateHz && chunk.sample_rate_hz <= kMaxSampleRateHz)) {
    std::ostringstream os;
    os << "source chunk: a sample rate of " << chunk.sample_rate_hz << " Hz is outside [" << kMinSampleRateHz
       << ", " << kMaxSampleRateHz << "] Hz";
    throw InputError(os.str());
  }
  AudioBuffer mono = mixToMono(chunk);
  for (float& v : mono.channels[0]) {
    if (!std::isfinite(v)) {
      v = 0.0f;
      ++counters_.non_finite_samples;
    }
  }
  std::string note;
  if (chunk.sample_rate_hz != last_rate_hz_) {
    if (last_rate_hz_ != 0.0 || chunk.sample_rate_hz != kInternalSampleRateHz) {
      std::ostringstream os;
      os << "the source arrives at " << chunk.sample_rate_hz << " Hz"
         << (chunk.sample_rate_hz == kInternalSampleRateHz ? "" : "; resampled to 48000 Hz");
      note = os.str();
    }
    last_rate_hz_ = chunk.sample_rate_hz;
    resampler_.reset();
    if (chunk.sample_rate_hz != kInternalSampleRateHz) {
      resampler_ = std::make_unique<StreamResampler>(chunk.sample_rate_hz, kInternalSampleRateHz);
    }
  }
  const std::vector<float>* samples = &mono.channels[0];
  if (resampler_) {
    scratch_.clear();
    resampler_->process(mono.channels[0].data(), mono.frameCount(), scratch_);
    samples = &scratch_;
    ++counters_.resampled_chunks;
  }
  queue_.insert(queue_.end(), samples->begin(), samples->end());
  if (queue_.size() > max_queued_) {
    const std::size_t excess = queue_.size() - max_queued_;
    queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(excess));
    counters_.overflow_samples += excess;
  }
  return note;
}

void SourceQueue::read(float* out, std::size_t count) {
  if (!playing_ && queue_.size() >= std::max<std::size_t>(prebuffer_, 1)) playing_ = true;
  if (!playing_) {
    std::fill(out, out + count, 0.0f);
    return;
  }
  const std::size_t n = std::min(count, queue_.size());
  std::copy_n(queue_.begin(), n, out);
  queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(n));
  if (n < count) {
    std::fill(out + n, out + count, 0.0f);
    counters_.underrun_samples += count - n;
    playing_ = false;  // wait for the prebuffer again rather than stutter
  }
}

void SourceQueue::skip(std::size_t count) {
  const std::size_t n = std::min(count, queue_.size());
  queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(n));
}

}  // namespace room_reverb::core
