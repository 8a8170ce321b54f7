#include "room_reverb/audio/stream_resampler.h"

#include <samplerate.h>

#include <sstream>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

struct StreamResampler::State {
  SRC_STATE* converter = nullptr;
  ~State() {
    if (converter != nullptr) src_delete(converter);
  }
};

StreamResampler::StreamResampler(double input_rate_hz, double output_rate_hz)
    : input_rate_hz_(input_rate_hz), output_rate_hz_(output_rate_hz), state_(std::make_unique<State>()) {
  for (double rate : {input_rate_hz, output_rate_hz}) {
    if (!(rate >= kMinSampleRateHz && rate <= kMaxSampleRateHz)) {
      std::ostringstream os;
      os << "stream resampler: a rate of " << rate << " Hz is outside [" << kMinSampleRateHz << ", "
         << kMaxSampleRateHz << "] Hz";
      throw InputError(os.str());
    }
  }
  int error = 0;
  // Medium quality: 97 dB of stop-band rejection for a quarter of the best converter's
  // cost, which a source stream (not a measurement) does not need.
  state_->converter = src_new(SRC_SINC_MEDIUM_QUALITY, 1, &error);
  if (state_->converter == nullptr) throw InputError(std::string("stream resampler: ") + src_strerror(error));
}

StreamResampler::~StreamResampler() = default;

void StreamResampler::process(const float* input, std::size_t count, std::vector<float>& output) {
  const double ratio = output_rate_hz_ / input_rate_hz_;
  scratch_.resize(static_cast<std::size_t>(static_cast<double>(count) * ratio) + 64);
  SRC_DATA data{};
  data.data_in = input;
  data.input_frames = static_cast<long>(count);
  data.src_ratio = ratio;
  data.end_of_input = 0;
  // The converter may keep input back; loop until it has taken all of it.
  while (data.input_frames > 0) {
    data.data_out = scratch_.data();
    data.output_frames = static_cast<long>(scratch_.size());
    const int error = src_process(state_->converter, &data);
    if (error != 0) throw InputError(std::string("stream resampler: ") + src_strerror(error));
    output.insert(output.end(), scratch_.begin(), scratch_.begin() + data.output_frames_gen);
    data.data_in += data.input_frames_used;
    data.input_frames -= data.input_frames_used;
    if (data.input_frames_used == 0 && data.output_frames_gen == 0) break;
  }
}

void StreamResampler::reset() { src_reset(state_->converter); }

}  // namespace room_reverb::core
