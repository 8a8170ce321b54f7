#include "sample_ring.h"

#include <algorithm>

namespace room_reverb::core {

namespace {

std::size_t nextPowerOfTwo(std::size_t n) {
  std::size_t p = 1;
  while (p < n) p *= 2;
  return p;
}

}  // namespace

SampleRing::SampleRing(std::size_t channels, std::size_t min_length)
    : mask_(nextPowerOfTwo(std::max<std::size_t>(min_length, 1)) - 1),
      channels_(channels, std::vector<float>(mask_ + 1, 0.0f)) {}

template <typename F>
void SampleRing::forEachSpan(std::int64_t frame, std::size_t count, F f) const {
  // Two's complement makes the mask work for negative frames too.
  const std::size_t position = static_cast<std::size_t>(static_cast<std::uint64_t>(frame)) & mask_;
  const std::size_t first = std::min(count, length() - position);
  f(position, 0, first);
  if (first < count) f(0, first, count - first);
}

void SampleRing::write(std::size_t channel, std::int64_t frame, const float* samples, std::size_t count) {
  float* ring = channels_[channel].data();
  forEachSpan(frame, count, [&](std::size_t at, std::size_t offset, std::size_t n) {
    std::copy_n(samples + offset, n, ring + at);
  });
}

void SampleRing::add(std::size_t channel, std::int64_t frame, const float* samples, std::size_t count) {
  float* ring = channels_[channel].data();
  forEachSpan(frame, count, [&](std::size_t at, std::size_t offset, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) ring[at + k] += samples[offset + k];
  });
}

void SampleRing::read(std::size_t channel, std::int64_t frame, float* samples, std::size_t count) const {
  const float* ring = channels_[channel].data();
  forEachSpan(frame, count, [&](std::size_t at, std::size_t offset, std::size_t n) {
    std::copy_n(ring + at, n, samples + offset);
  });
}

void SampleRing::clear(std::int64_t frame, std::size_t count) {
  for (auto& channel : channels_) {
    float* ring = channel.data();
    forEachSpan(frame, count, [&](std::size_t at, std::size_t, std::size_t n) { std::fill_n(ring + at, n, 0.0f); });
  }
}

void SampleRing::clearAll() {
  for (auto& channel : channels_) std::fill(channel.begin(), channel.end(), 0.0f);
}

}  // namespace room_reverb::core
