#include "room_reverb/audio/resample.h"

#include <samplerate.h>

#include <cmath>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

AudioBuffer resample(const AudioBuffer& buffer, double target_rate_hz) {
  validateAudioBuffer(buffer, "resampler input");
  if (!(target_rate_hz >= kMinSampleRateHz && target_rate_hz <= kMaxSampleRateHz)) {
    std::ostringstream os;
    os << "cannot resample to " << target_rate_hz << " Hz";
    throw InputError(os.str());
  }
  if (buffer.sample_rate_hz == target_rate_hz) return buffer;

  const double ratio = target_rate_hz / buffer.sample_rate_hz;
  const std::size_t channels = buffer.channelCount();
  const auto out_frames =
      static_cast<std::size_t>(std::llround(static_cast<double>(buffer.frameCount()) * ratio));
  const std::vector<float> input = interleave(buffer);
  // The sinc converter delays nothing but needs room for its own tail: give it a few
  // extra frames and keep the time-aligned part.
  std::vector<float> output((out_frames + 64) * channels, 0.0f);

  SRC_DATA data{};
  data.data_in = input.data();
  data.input_frames = static_cast<long>(buffer.frameCount());
  data.data_out = output.data();
  data.output_frames = static_cast<long>(out_frames + 64);
  data.src_ratio = ratio;
  const int error = src_simple(&data, SRC_SINC_BEST_QUALITY, static_cast<int>(channels));
  if (error != 0) throw InputError(std::string("resampling failed: ") + src_strerror(error));
  output.resize(out_frames * channels);
  return deinterleave(output, channels, target_rate_hz);
}

}  // namespace room_reverb::core
