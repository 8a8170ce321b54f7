#pragma once
// Channels of samples addressed by absolute stream frame, of which the last length()
// frames are kept: the input history the convolver's levels transform, and the output
// each filter set's levels write ahead of the frames being played.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace room_reverb::core {

class SampleRing {
 public:
  // Holds at least `min_length` frames per channel (rounded up to a power of two, so a
  // frame's position is one mask), all zero.
  SampleRing(std::size_t channels, std::size_t min_length);

  std::size_t length() const { return mask_ + 1; }

  // Frames [frame, frame + count) of `channel`; count <= length(). Negative frames are the
  // silence before the stream (as long as the ring has not wrapped onto them).
  void write(std::size_t channel, std::int64_t frame, const float* samples, std::size_t count);
  void add(std::size_t channel, std::int64_t frame, const float* samples, std::size_t count);
  void read(std::size_t channel, std::int64_t frame, float* samples, std::size_t count) const;
  // Zeroes frames [frame, frame + count) of every channel, once they are consumed.
  void clear(std::int64_t frame, std::size_t count);
  void clearAll();

 private:
  // Calls f(position, offset, n) for the one or two contiguous spans frame..frame+count
  // occupies in the ring, offset being the span's start within [0, count).
  template <typename F>
  void forEachSpan(std::int64_t frame, std::size_t count, F f) const;

  std::size_t mask_;
  std::vector<std::vector<float>> channels_;
};

}  // namespace room_reverb::core
