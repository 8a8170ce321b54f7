#include "room_reverb/binaural/late_order.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/convolution.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kFadeFrames = 256;       // 5.3 ms at 48 kHz
constexpr std::size_t kEqualiserTaps = 255;    // odd: zero phase about the middle tap
constexpr double kLargestGain = 4.0;           // +12 dB: a decoder's notch is not filled


}  // namespace

std::vector<float> lateOrderEqualiser(const BinauralDecoder& decoder) {
  if (decoder.order < 2) throw InputError("late order: the decoder must be of order 2 or 3 to cut orders above 1");
  std::size_t longest = 0;
  for (const Hrir& h : decoder.filters) longest = std::max({longest, h.left.size(), h.right.size()});
  RealFft fft(nextFastFftSize(std::max<std::size_t>(2 * longest, 4 * kEqualiserTaps)));
  std::vector<double> all(fft.spectrumSize(), 0.0), low(fft.spectrumSize(), 0.0);
  std::vector<float> padded(fft.size());
  std::vector<std::complex<float>> spectrum(fft.spectrumSize());
  for (std::size_t c = 0; c < decoder.filters.size(); ++c) {
    const int l = static_cast<int>(std::floor(std::sqrt(static_cast<double>(c))));
    const double diffuse_share = 1.0 / (2.0 * l + 1.0);
    for (const std::vector<float>* ear : {&decoder.filters[c].left, &decoder.filters[c].right}) {
      std::fill(padded.begin(), padded.end(), 0.0f);
      std::copy(ear->begin(), ear->end(), padded.begin());
      fft.forward(padded.data(), spectrum.data());
      for (std::size_t k = 0; k < spectrum.size(); ++k) {
        const double power = diffuse_share * std::norm(spectrum[k]);
        all[k] += power;
        if (l <= 1) low[k] += power;
      }
    }
  }
  for (std::size_t k = 0; k < spectrum.size(); ++k) {
    const double gain = low[k] > 0.0 ? std::sqrt(all[k] / low[k]) : 1.0;
    spectrum[k] = static_cast<float>(std::clamp(gain, 1.0 / kLargestGain, kLargestGain));
  }
  std::vector<float> impulse(fft.size());
  fft.inverse(spectrum.data(), impulse.data());
  // The real, even spectrum's inverse is even about 0: fold it about the middle tap,
  // Hann-windowed.
  const std::size_t half = kEqualiserTaps / 2;
  std::vector<float> taps(kEqualiserTaps);
  for (std::size_t i = 0; i < kEqualiserTaps; ++i) {
    const long lag = static_cast<long>(i) - static_cast<long>(half);
    const std::size_t at = lag >= 0 ? static_cast<std::size_t>(lag) : fft.size() - static_cast<std::size_t>(-lag);
    const double window = 0.5 + 0.5 * std::cos(kPi * static_cast<double>(lag) / static_cast<double>(half + 1));
    taps[i] = static_cast<float>(window * impulse[at]);
  }
  return taps;
}

AudioBuffer reduceLateOrder(const AudioBuffer& ambix, const BinauralDecoder& decoder, double full_order_s) {
  if (!std::isfinite(full_order_s) || full_order_s < 0.0) {
    throw InputError("late order: the time to keep all orders must be a finite number of seconds >= 0");
  }
  const int order = ambixOrder(ambix, "late order: the response");
  if (order > decoder.order) {
    throw InputError("late order: a response of " + std::to_string(ambix.channelCount()) +
                     " channels for a decoder of order " + std::to_string(decoder.order));
  }
  const auto centre = static_cast<std::size_t>(std::llround(full_order_s * ambix.sample_rate_hz));
  const std::size_t fade_start = centre > kFadeFrames / 2 ? centre - kFadeFrames / 2 : 0;
  const std::size_t fade_end = fade_start + kFadeFrames;
  if (order <= 1 || ambix.frameCount() <= fade_start) return ambix;
  const std::vector<float> equaliser = lateOrderEqualiser(decoder);
  const std::size_t half = equaliser.size() / 2;
  const std::size_t frames = ambix.frameCount();
  // w(n): 0 before the fade, 1 after it.
  const auto tailWeight = [&](std::size_t n) {
    if (n < fade_start) return 0.0;
    if (n >= fade_end) return 1.0;
    return 0.5 - 0.5 * std::cos(kPi * (static_cast<double>(n - fade_start) + 0.5) / static_cast<double>(kFadeFrames));
  };
  AudioBuffer out = ambix;
  for (std::size_t c = 0; c < ambix.channelCount(); ++c) {
    const std::vector<float>& h = ambix.channels[c];
    std::vector<float>& y = out.channels[c];
    if (c >= 4) {
      for (std::size_t n = fade_start; n < frames; ++n) y[n] = static_cast<float>(h[n] * (1.0 - tailWeight(n)));
      continue;
    }
    // y = h (1 - w) + e * (h w), the zero-phase equaliser centred on each sample (an FFT
    // convolution of the tail, shifted back by half the equaliser). The output keeps the
    // response's length: what the equaliser spreads past its end is cut.
    std::vector<float> tail(frames - fade_start);
    for (std::size_t n = fade_start; n < frames; ++n) {
      const double w = tailWeight(n);
      tail[n - fade_start] = static_cast<float>(h[n] * w);
      y[n] = static_cast<float>(h[n] * (1.0 - w));
    }
    const std::vector<float> shaped = fftConvolve(tail, equaliser);
    for (std::size_t i = 0; i < shaped.size(); ++i) {
      // shaped[i] lands at fade_start + i - half.
      if (fade_start + i < half) continue;
      const std::size_t n = fade_start + i - half;
      if (n >= frames) break;
      y[n] += shaped[i];
    }
  }
  return out;
}

}  // namespace room_reverb::core
