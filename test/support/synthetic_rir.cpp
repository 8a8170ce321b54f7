#include "synthetic_rir.h"

#include <cmath>
#include <complex>
#include <random>

#include "room_reverb/audio/fft.h"

namespace room_reverb::test {
namespace {

double decayPerSample(double t60_s) { return 6.0 * std::log(10.0) / (t60_s * kFs); }

}  // namespace

std::vector<float> whiteNoise(std::size_t length, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::vector<float> x(length);
  for (auto& v : x) v = normal(rng);
  return x;
}

std::vector<float> exponentialDecayNoise(std::size_t length, double t60_s, std::size_t onset,
                                         std::uint32_t seed) {
  std::vector<float> x = whiteNoise(length, seed);
  const double delta = decayPerSample(t60_s);
  for (std::size_t n = 0; n < length; ++n) {
    x[n] = n < onset ? 0.0f : static_cast<float>(x[n] * std::exp(-0.5 * delta * (n - onset)));
  }
  return x;
}

std::vector<float> exactEnergyDecay(std::size_t length, double t60_s, std::size_t onset,
                                    std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution sign(0.5);
  const double delta = decayPerSample(t60_s);
  std::vector<float> x(length, 0.0f);
  for (std::size_t n = onset; n < length; ++n) {
    x[n] = static_cast<float>((sign(rng) ? 1.0 : -1.0) * std::exp(-0.5 * delta * (n - onset)));
  }
  return x;
}

std::vector<float> bandwiseDecayNoise(std::size_t length, const std::vector<core::FrequencyBand>& bands,
                                      const std::vector<double>& t60_s, std::size_t onset,
                                      std::uint32_t seed) {
  std::vector<float> sum(length, 0.0f);
  core::RealFft fft(core::nextFastFftSize(length));
  for (std::size_t b = 0; b < bands.size(); ++b) {
    // Ideal band-pass over the central half of the band (a quarter of the band width
    // either side of the centre on the log axis), in the frequency domain.
    std::vector<float> noise = whiteNoise(fft.size(), seed + 7919u * static_cast<std::uint32_t>(b));
    auto spectrum = fft.forward(noise);
    const double quarter = 0.25 * std::log2(bands[b].upper_hz / bands[b].lower_hz);
    const double low = bands[b].center_hz * std::pow(2.0, -quarter);
    const double high = bands[b].center_hz * std::pow(2.0, quarter);
    for (std::size_t k = 0; k < spectrum.size(); ++k) {
      const double f = k * kFs / fft.size();
      if (f < low || f > high) spectrum[k] = 0.0f;
    }
    noise = fft.inverse(spectrum);
    double power = 0.0;
    for (float v : noise) power += static_cast<double>(v) * v;
    power /= noise.size();
    const double gain = 1.0 / std::sqrt(power * bands.size());
    const double delta = decayPerSample(t60_s[b]);
    for (std::size_t n = onset; n < length; ++n) {
      sum[n] += static_cast<float>(gain * noise[n] * std::exp(-0.5 * delta * (n - onset)));
    }
  }
  return sum;
}

std::vector<float> bandwiseDecayRandomFm(std::size_t length, const std::vector<core::FrequencyBand>& bands,
                                         const std::vector<double>& t60_s, std::size_t onset,
                                         std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<float> sum(length, 0.0f);
  const double two_pi = 2.0 * M_PI;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    // Frequency on the log axis: centre * 2^(depth * m(t)), m(t) in [-1, 1] a sum of three
    // slow sinusoids (0.3-1.5 Hz) with random rates and phases. The depth keeps the tone
    // and most of its FM sidebands inside the central half of the band.
    const double depth = 0.15 * std::log2(bands[b].upper_hz / bands[b].lower_hz);
    double rates[3], phases[3];
    for (int i = 0; i < 3; ++i) {
      rates[i] = 0.3 + 1.2 * uniform(rng);
      phases[i] = two_pi * uniform(rng);
    }
    double phase = two_pi * uniform(rng);
    const double amplitude = std::sqrt(2.0 / bands.size());  // mean-square 1/bands at the onset
    const double delta = decayPerSample(t60_s[b]);
    for (std::size_t n = onset; n < length; ++n) {
      const double t = n / kFs;
      double m = 0.0;
      for (int i = 0; i < 3; ++i) m += std::sin(two_pi * rates[i] * t + phases[i]) / 3.0;
      const double frequency = bands[b].center_hz * std::pow(2.0, depth * m);
      phase += two_pi * frequency / kFs;
      sum[n] += static_cast<float>(amplitude * std::cos(phase) * std::exp(-0.5 * delta * (n - onset)));
    }
  }
  return sum;
}

void addNoiseFloor(std::vector<float>& signal, double level_db, std::uint32_t seed) {
  const std::vector<float> noise = whiteNoise(signal.size(), seed);
  const float gain = static_cast<float>(std::pow(10.0, level_db / 20.0));
  for (std::size_t n = 0; n < signal.size(); ++n) signal[n] += gain * noise[n];
}

double energy(const std::vector<float>& x) {
  double e = 0.0;
  for (float v : x) e += static_cast<double>(v) * v;
  return e;
}

}  // namespace room_reverb::test
