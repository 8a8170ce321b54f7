#pragma once
// Sample-rate conversion of a stream that arrives in chunks (a source topic at 44.1 kHz
// feeding the 48 kHz renderer): libsamplerate's converter kept between calls, so chunk
// boundaries leave no trace. resample() (resample.h) converts whole buffers instead and
// cannot be applied chunk by chunk: each call would restart the filter and click.
//
// The converter delays its output by about half its filter (some tens of samples at the
// output rate for the medium-quality sinc); a stream is only ever shifted by that constant.
#include <cstddef>
#include <memory>
#include <vector>

namespace room_reverb::core {

class StreamResampler {
 public:
  // Mono, from `input_rate_hz` to `output_rate_hz`, each within the project's accepted
  // range (InputError otherwise).
  StreamResampler(double input_rate_hz, double output_rate_hz);
  ~StreamResampler();
  StreamResampler(const StreamResampler&) = delete;
  StreamResampler& operator=(const StreamResampler&) = delete;

  double inputRateHz() const { return input_rate_hz_; }
  double outputRateHz() const { return output_rate_hz_; }

  // Converts `count` input samples and appends what the converter releases to `output`
  // (on average count * output/input samples). Non-finite input must be cleaned first.
  void process(const float* input, std::size_t count, std::vector<float>& output);

  // Forgets the history (a new stream starts).
  void reset();

 private:
  struct State;
  double input_rate_hz_;
  double output_rate_hz_;
  std::unique_ptr<State> state_;
  std::vector<float> scratch_;
};

}  // namespace room_reverb::core
