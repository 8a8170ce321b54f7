#include "room_reverb/audio/lowpass_filter.h"

#include <cmath>
#include <string>

#include "room_reverb/audio/convolution.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

std::vector<float> windowedSincLowpass(double cutoff_hz, double sample_rate_hz, std::size_t taps) {
  if (taps == 0 || taps % 2 == 0) {
    throw InputError("a linear-phase low-pass needs an odd number of taps (got " + std::to_string(taps) + ")");
  }
  if (!(cutoff_hz > 0.0 && cutoff_hz < sample_rate_hz / 2.0)) {
    throw InputError("a low-pass cutoff must lie between 0 Hz and the Nyquist frequency");
  }
  const double fc = cutoff_hz / sample_rate_hz;  // cycles per sample
  const double middle = static_cast<double>(taps - 1) / 2.0;
  std::vector<double> h(taps);
  double sum = 0.0;
  for (std::size_t i = 0; i < taps; ++i) {
    const double x = static_cast<double>(i) - middle;
    const double sinc = x == 0.0 ? 2.0 * fc : std::sin(2.0 * kPi * fc * x) / (kPi * x);
    const double u = taps == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(taps - 1);
    const double window = 0.42 - 0.5 * std::cos(2.0 * kPi * u) + 0.08 * std::cos(4.0 * kPi * u);
    h[i] = sinc * window;
    sum += h[i];
  }
  // Unit gain at 0 Hz exactly: the window takes a little off the truncated sinc's sum.
  std::vector<float> coefficients(taps);
  for (std::size_t i = 0; i < taps; ++i) coefficients[i] = static_cast<float>(h[i] / sum);
  return coefficients;
}

AudioBuffer lowpassFiltered(const AudioBuffer& audio, double cutoff_hz, std::size_t taps) {
  validateAudioBuffer(audio, "the signal to low-pass");
  const std::vector<float> h = windowedSincLowpass(cutoff_hz, audio.sample_rate_hz, taps);
  const std::size_t delay = (taps - 1) / 2;
  AudioBuffer out;
  out.sample_rate_hz = audio.sample_rate_hz;
  for (const std::vector<float>& channel : audio.channels) {
    const std::vector<float> full = fftConvolve(channel, h);  // frames + taps - 1
    out.channels.emplace_back(full.begin() + static_cast<std::ptrdiff_t>(delay), full.end());
  }
  return out;
}

}  // namespace room_reverb::core
