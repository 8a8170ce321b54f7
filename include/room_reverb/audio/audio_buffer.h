#pragma once
// Multichannel audio held as planar channels of float samples at one sample rate.
#include <cstddef>
#include <string>
#include <vector>

namespace room_reverb::core {

// Sample rates the project accepts anywhere (inputs outside are an InputError).
constexpr double kMinSampleRateHz = 8000.0;
constexpr double kMaxSampleRateHz = 768000.0;
// The project's internal rate (DESIGN.md: "48 kHz inside").
constexpr double kInternalSampleRateHz = 48000.0;

struct AudioBuffer {
  double sample_rate_hz = kInternalSampleRateHz;
  // channels[c][n]: sample n of channel c, linear full scale (1.0 = 0 dBFS).
  std::vector<std::vector<float>> channels;

  std::size_t channelCount() const { return channels.size(); }
  std::size_t frameCount() const { return channels.empty() ? 0 : channels.front().size(); }
  double durationS() const { return sample_rate_hz > 0.0 ? frameCount() / sample_rate_hz : 0.0; }
};

// A buffer of `channel_count` silent channels of `frame_count` samples.
AudioBuffer makeSilentBuffer(std::size_t channel_count, std::size_t frame_count,
                             double sample_rate_hz);

// True when no sample is NaN or infinite.
bool allSamplesFinite(const std::vector<float>& samples);

// Throws InputError, naming `what` (e.g. the file name), unless the buffer has at least
// one channel, channels of equal length, a sample rate within [kMinSampleRateHz,
// kMaxSampleRateHz] and only finite samples.
void validateAudioBuffer(const AudioBuffer& buffer, const std::string& what);

// Interleave (frame-major, as WAV files and ROS messages store it) and back.
std::vector<float> interleave(const AudioBuffer& buffer);
AudioBuffer deinterleave(const std::vector<float>& samples, std::size_t channel_count,
                         double sample_rate_hz);

}  // namespace room_reverb::core
