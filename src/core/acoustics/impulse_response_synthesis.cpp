#include "room_reverb/acoustics/impulse_response_synthesis.h"

#include <cmath>
#include <complex>
#include <random>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kTapLength = 2048;  // 43 ms at 48 kHz: resolves the 63 Hz band's gain

int orderOfChannel(std::size_t acn) { return static_cast<int>(std::floor(std::sqrt(static_cast<double>(acn)))); }

void addEarlyPaths(const std::vector<SpecularPath>& paths, const BandFilterBank& bank, int order, AudioBuffer& out) {
  const double fs = out.sample_rate_hz;
  const auto frames = static_cast<long>(out.frameCount());
  RealFft fft(kTapLength);
  // Squared band responses on the tap's frequency grid.
  std::vector<std::array<double, kOctaveBandCount>> band_power(fft.spectrumSize());
  for (std::size_t k = 0; k < fft.spectrumSize(); ++k) {
    for (int b = 0; b < kOctaveBandCount; ++b) {
      const double g = bank.gain(static_cast<std::size_t>(b), k * fs / kTapLength);
      band_power[k][b] = g * g;
    }
  }

  std::vector<std::complex<float>> spectrum(fft.spectrumSize());
  std::vector<float> tap(kTapLength);
  const long half = static_cast<long>(kTapLength / 2);
  for (const auto& path : paths) {
    const double delay = path.delay_s * fs;
    const auto whole = static_cast<long>(std::floor(delay));
    if (whole - half >= frames) continue;
    const double fraction = delay - static_cast<double>(whole);
    for (std::size_t k = 0; k < spectrum.size(); ++k) {
      double power = 0.0;
      for (int b = 0; b < kOctaveBandCount; ++b) power += path.pressure_gain[b] * path.pressure_gain[b] * band_power[k][b];
      // Zero phase, centred in the tap, plus the fractional part of the delay.
      const double phase = -2.0 * kPi * k * (static_cast<double>(half) + fraction) / kTapLength;
      spectrum[k] = std::polar(static_cast<float>(std::sqrt(power)), static_cast<float>(phase));
    }
    fft.inverse(spectrum.data(), tap.data());
    const std::vector<double> harmonics = sn3dHarmonics(order, path.arrival_direction);
    for (std::size_t n = 0; n < kTapLength; ++n) {
      const long index = whole - half + static_cast<long>(n);
      if (index < 0 || index >= frames) continue;
      // Hann window centred on the tap's true centre, so it does not shift the delay.
      const double offset = static_cast<double>(n) - static_cast<double>(half) - fraction;
      const double window = 0.5 + 0.5 * std::cos(2.0 * kPi * offset / kTapLength);
      const double sample = tap[n] * window;
      for (std::size_t c = 0; c < out.channelCount(); ++c) out.channels[c][static_cast<std::size_t>(index)] += static_cast<float>(harmonics[c] * sample);
    }
  }
}

// Probability of an event per sample at time t: the reflection density 4 pi c^3 t^2 / V
// (Kuttruff), capped.
double eventProbability(double t, const SynthesisOptions& o) {
  const double growth = 4.0 * kPi * std::pow(o.speed_of_sound_m_s, 3) / o.room_volume_m3;
  return std::min(o.max_event_rate_per_s, growth * t * t) / o.sample_rate_hz;
}

// Signed unit impulses at Poisson times with that density.
std::vector<float> poissonSequence(std::size_t frames, const SynthesisOptions& o, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<float> x(frames, 0.0f);
  for (std::size_t n = 0; n < frames; ++n) {
    if (u(rng) < eventProbability(n / o.sample_rate_hz, o)) x[n] = u(rng) < 0.5 ? -1.0f : 1.0f;
  }
  return x;
}

// The realised energy per sample of a band signal, averaged over a centred window. The
// late field is scaled by target / realised energy: averaging over a few of the band's
// correlation times keeps that gain smooth (no spreading into other bands) while still
// taking out the noise's own slow level wander, which would otherwise scatter the decay
// time from one seed to the next (the ISO 3382-2 scatter of a single noise realisation).
std::vector<double> smoothedEnergy(const std::vector<float>& x, std::size_t window) {
  std::vector<double> prefix(x.size() + 1, 0.0);
  for (std::size_t n = 0; n < x.size(); ++n) prefix[n + 1] = prefix[n] + static_cast<double>(x[n]) * x[n];
  std::vector<double> out(x.size());
  const std::size_t half = window / 2;
  for (std::size_t n = 0; n < x.size(); ++n) {
    const std::size_t first = n > half ? n - half : 0;
    const std::size_t last = std::min(x.size(), n + half + 1);
    out[n] = (prefix[last] - prefix[first]) / static_cast<double>(last - first);
  }
  return out;
}

// Per-sample energy targets from a histogram, linearly interpolated between bin centres
// (steps at bin edges would spread a low band's energy into the high bands).
double interpolatedTarget(const std::vector<double>& per_bin, double position_in_bins) {
  const double x = position_in_bins - 0.5;
  if (x <= 0.0) return per_bin.empty() ? 0.0 : per_bin.front();
  const auto i = static_cast<std::size_t>(x);
  if (i + 1 >= per_bin.size()) return per_bin.empty() ? 0.0 : per_bin.back();
  const double f = x - static_cast<double>(i);
  return (1.0 - f) * per_bin[i] + f * per_bin[i + 1];
}

void addLateField(const EnergyHistogram& late, const BandFilterBank& bank, const SynthesisOptions& o, AudioBuffer& out) {
  std::mt19937_64 rng(o.seed);
  const std::size_t frames = out.frameCount();
  const std::size_t channels = out.channelCount();
  const int order = static_cast<int>(std::lround(std::sqrt(static_cast<double>(channels)))) - 1;
  const double bin_frames = late.binS() * o.sample_rate_hz;
  const double to_pressure = 4.0 * kPi;  // J/m^2 per emitted J -> energy re the direct sound at 1 m
  // One independent sequence per channel: channel 0 carries the whole energy and the
  // directional part, the others add the diffuse part.
  std::vector<std::vector<std::vector<float>>> bands(channels);
  for (std::size_t c = 0; c < channels; ++c) bands[c] = bank.split(poissonSequence(frames, o, rng));

  for (int b = 0; b < kOctaveBandCount; ++b) {
    const FrequencyBand& band = bank.bands()[static_cast<std::size_t>(b)];
    const auto window = static_cast<std::size_t>(std::max(5.0 * bin_frames, 4.0 * o.sample_rate_hz / (band.upper_hz - band.lower_hz)));
    std::vector<std::vector<double>> realised(channels);
    for (std::size_t c = 0; c < channels; ++c) realised[c] = smoothedEnergy(bands[c][static_cast<std::size_t>(b)], window);
    // Per bin: energy per sample, directional fraction and the direction's harmonics.
    std::vector<double> energy(late.bins()), directional(late.bins());
    std::vector<std::vector<double>> harmonics(late.bins());
    for (std::size_t bin = 0; bin < late.bins(); ++bin) {
      energy[bin] = to_pressure * late.energy(bin, b) / bin_frames;
      const Eigen::Vector3d flux = to_pressure * late.flux(bin, b) / bin_frames;
      directional[bin] = energy[bin] > 0.0 ? std::min(1.0, flux.norm() / energy[bin]) : 0.0;
      harmonics[bin] = sn3dHarmonics(order, flux.norm() > 0.0 ? Eigen::Vector3d(flux.normalized()) : Eigen::Vector3d::UnitX());
    }
    for (std::size_t n = 0; n < frames; ++n) {
      const double position = n / bin_frames;
      const double target = interpolatedTarget(energy, position);
      if (target <= 0.0 || realised[0][n] <= 0.0) continue;
      const auto bin = std::min(late.bins() - 1, static_cast<std::size_t>(position));
      const double main = std::sqrt(target / realised[0][n]) * bands[0][static_cast<std::size_t>(b)][n];
      out.channels[0][n] += static_cast<float>(main);
      for (std::size_t c = 1; c < channels; ++c) {
        double v = main * harmonics[bin][c] * std::sqrt(directional[bin]);
        if (realised[c][n] > 0.0) {
          const double diffuse = target * (1.0 - directional[bin]) / (2.0 * orderOfChannel(c) + 1.0);
          v += std::sqrt(diffuse / realised[c][n]) * bands[c][static_cast<std::size_t>(b)][n];
        }
        out.channels[c][n] += static_cast<float>(v);
      }
    }
  }
}

}  // namespace

AudioBuffer synthesizeImpulseResponse(const std::vector<SpecularPath>& paths, const EnergyHistogram* late,
                                      const SynthesisOptions& options) {
  if (options.ambisonic_order < 0 || options.ambisonic_order > kMaxAmbisonicOrder) {
    throw InputError("ambisonic order must be 0 to 3");
  }
  if (!(options.duration_s > 0.0)) throw InputError("the response duration must be positive");
  if (!(options.room_volume_m3 > 0.0)) throw InputError("the room volume must be positive");
  const auto frames = static_cast<std::size_t>(std::ceil(options.duration_s * options.sample_rate_hz));
  AudioBuffer out = makeSilentBuffer(static_cast<std::size_t>(ambisonicChannelCount(options.ambisonic_order)), frames,
                                     options.sample_rate_hz);
  const BandFilterBank bank(standardBands(BandResolution::kOctave), options.sample_rate_hz);
  addEarlyPaths(paths, bank, options.ambisonic_order, out);
  if (late) addLateField(*late, bank, options, out);
  return out;
}

}  // namespace room_reverb::core
