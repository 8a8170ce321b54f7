#include "room_reverb/audio/crossover.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/audio/fft.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

double crossoverLowGain(double frequency_hz, double crossover_hz, double width_octaves) {
  if (frequency_hz <= 0.0) return 1.0;
  const double x = std::log2(frequency_hz / crossover_hz) / width_octaves + 0.5;  // 0 .. 1 across the transition
  if (x <= 0.0) return 1.0;
  if (x >= 1.0) return 0.0;
  const double c = std::cos(0.5 * 3.14159265358979323846 * x);
  return c * c;
}

AudioBuffer joinAtCrossover(const AudioBuffer& low, const AudioBuffer& high, double crossover_hz, double width_octaves) {
  if (low.sample_rate_hz != high.sample_rate_hz) throw InputError("crossover: the two responses have different sample rates");
  if (!(crossover_hz > 0.0) || !(crossover_hz < 0.5 * high.sample_rate_hz)) {
    throw InputError("crossover: the frequency must lie between 0 and the Nyquist frequency");
  }
  if (!(width_octaves > 0.0)) throw InputError("crossover: the width must be positive");
  AudioBuffer out = high;
  const std::size_t frames = high.frameCount();
  if (frames == 0) return out;
  // Room for the zero-phase filter's ringing on both sides (its impulse response lasts a
  // few periods of the transition band's width), so that it does not wrap around.
  const double transition_hz = crossover_hz * (std::exp2(0.5 * width_octaves) - std::exp2(-0.5 * width_octaves));
  const auto pad = static_cast<std::size_t>(std::ceil(std::max(0.05, 8.0 / transition_hz) * high.sample_rate_hz));
  RealFft fft(nextFastFftSize(frames + 2 * pad));
  std::vector<float> gain(fft.spectrumSize());
  for (std::size_t k = 0; k < gain.size(); ++k) {
    gain[k] = static_cast<float>(crossoverLowGain(k * high.sample_rate_hz / fft.size(), crossover_hz, width_octaves));
  }
  std::vector<float> time(fft.size());
  std::vector<std::complex<float>> spectrum(fft.spectrumSize());
  for (std::size_t ch = 0; ch < std::min(low.channelCount(), high.channelCount()); ++ch) {
    // out = high + H (low - high): one filtering per channel.
    std::fill(time.begin(), time.end(), 0.0f);
    for (std::size_t n = 0; n < frames; ++n) {
      time[pad + n] = (n < low.channels[ch].size() ? low.channels[ch][n] : 0.0f) - high.channels[ch][n];
    }
    fft.forward(time.data(), spectrum.data());
    for (std::size_t k = 0; k < spectrum.size(); ++k) spectrum[k] *= gain[k];
    fft.inverse(spectrum.data(), time.data());
    for (std::size_t n = 0; n < frames; ++n) out.channels[ch][n] += time[pad + n];
  }
  return out;
}

}  // namespace room_reverb::core
