#include "room_reverb/acoustics/impulse_response_synthesis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "room_reverb/acoustics/late_field_noise.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kTapLength = kPathTapLength;

int orderOfChannel(std::size_t acn) { return static_cast<int>(std::floor(std::sqrt(static_cast<double>(acn)))); }

// The bands a response is synthesised from and where their energies come from: band t of
// `bank` is band t / views of view t % views (views: 1 for octaves, 3 for the thirds of
// every octave, AcousticScene::thirdOctaveBands), so the bank's bands run up the spectrum.
struct BandViews {
  std::vector<const std::vector<SpecularPath>*> paths;  // per view, the same arrivals
  std::vector<const EnergyHistogram*> late;             // per view (null entries: no late part)
  std::size_t views() const { return paths.size(); }
  int octaveOf(std::size_t t) const { return static_cast<int>(t / views()); }
  std::size_t viewOf(std::size_t t) const { return t % views(); }
};

void addEarlyPaths(const BandViews& in, const BandFilterBank& bank, int order, AudioBuffer& out) {
  const double fs = out.sample_rate_hz;
  const auto frames = static_cast<long>(out.frameCount());
  const std::size_t band_count = bank.bands().size();
  RealFft fft(kTapLength);
  // Squared band responses on the tap's frequency grid.
  std::vector<std::vector<double>> band_power(fft.spectrumSize(), std::vector<double>(band_count));
  for (std::size_t k = 0; k < fft.spectrumSize(); ++k) {
    for (std::size_t t = 0; t < band_count; ++t) {
      const double g = bank.gain(t, k * fs / kTapLength);
      band_power[k][t] = g * g;
    }
  }

  std::vector<std::complex<float>> spectrum(fft.spectrumSize());
  std::vector<float> tap(kTapLength);
  std::vector<double> gain_squared(band_count);
  const long half = static_cast<long>(kTapLength / 2);
  const std::vector<SpecularPath>& arrivals = *in.paths.front();
  for (std::size_t i = 0; i < arrivals.size(); ++i) {
    const SpecularPath& path = arrivals[i];
    const double delay = path.delay_s * fs;
    const auto whole = static_cast<long>(std::floor(delay));
    if (whole - half >= frames) continue;
    const double fraction = delay - static_cast<double>(whole);
    for (std::size_t t = 0; t < band_count; ++t) {
      const double g = (*in.paths[in.viewOf(t)])[i].pressure_gain[in.octaveOf(t)];
      gain_squared[t] = g * g;
    }
    for (std::size_t k = 0; k < spectrum.size(); ++k) {
      double power = 0.0;
      for (std::size_t t = 0; t < band_count; ++t) power += gain_squared[t] * band_power[k][t];
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

// The highest octave synthesised as a whole (nominal centre); thirds above it.
constexpr double kLastWholeOctaveHz = 500.0;

// The bands a response's energies are given in (its views' bands, BandViews): the nine
// octaves, or for three views the 27 thirds of the octaves, 50 Hz .. 20 kHz.
std::vector<FrequencyBand> viewBands(std::size_t views) {
  return views == 1 ? standardBands(BandResolution::kOctave) : thirdsOfTheOctaves();
}

// The bands the late noise is synthesised in. From octave energies: the octaves up to
// 500 Hz, their thirds from the 1 kHz octave up. From third-octave energies: the thirds.
//
// Why thirds: a band's noise reaches into its neighbours' crossovers, so with octave-wide
// synthesis bands a slowly decaying octave leaks its decay into the next octave's analysis
// (a 16 kHz band that should fall 160 dB/s is buried under the 8 kHz band's 65 dB/s after
// 0.1 s: T20 came out twice too long in the BRAS CR2 room). In a real room the decay rate
// changes smoothly with frequency; thirds with the spectral density interpolated between
// octave centres restore that. Why not thirds all the way down: a low third is so narrow
// that its noise's level wanders over hundreds of milliseconds, which scatters the low
// bands' C80 and D50 by several dB from one seed to the next, while there air absorption
// is negligible and neighbouring octaves decay at similar rates. Third-octave energies
// (a simulation in third octaves) are synthesised in thirds all the way down: there the
// thirds differ by what the materials say, and that is what was asked for.
std::vector<FrequencyBand> lateSynthesisBands(std::size_t views) {
  if (views != 1) return viewBands(views);
  std::vector<FrequencyBand> bands;
  for (const FrequencyBand& octave : standardBands(BandResolution::kOctave)) {
    if (octave.nominal_hz <= kLastWholeOctaveHz) bands.push_back(octave);
  }
  const double first_third_hz = bands.empty() ? 0.0 : bands.back().upper_hz;
  for (const FrequencyBand& third : standardBands(BandResolution::kThirdOctave)) {
    if (third.center_hz > first_third_hz) bands.push_back(third);
  }
  return bands;
}

// Effective noise bandwidth of each band, the integral of |H|^2 (Hz), on a fine grid over
// the band's support only (it is zero elsewhere; a band reaches at most one of its own
// widths past either edge).
std::vector<double> noiseBandwidthsHz(const BandFilterBank& bank) {
  constexpr int kSteps = 4096;
  std::vector<double> out(bank.bands().size(), 0.0);
  for (std::size_t b = 0; b < out.size(); ++b) {
    const FrequencyBand& band = bank.bands()[b];
    const double width = band.upper_hz / band.lower_hz;
    const double low = band.lower_hz / width;
    const double high = std::min(band.upper_hz * width, 0.5 * bank.sampleRateHz());
    const double step_hz = (high - low) / kSteps;
    for (int k = 0; k < kSteps; ++k) {
      const double g = bank.gain(b, low + (k + 0.5) * step_hz);
      out[b] += g * g * step_hz;
    }
  }
  return out;
}

// Per histogram bin, the late field's power spectral density (energy per sample per Hz) at
// each synthesis band: a histogram band's energy is what an impulsive, white source
// delivers in that band, so its density is the energy over the whole spectrum (fs / 2),
// interpolated between the given bands' centres (`nodes`, `per_octave` to an octave) as
// log density over log frequency. `owner` gets the node each band lies in (-1 for bands
// outside the nodes' range, which get nothing).
std::vector<std::vector<double>> synthesisBandDensities(const std::vector<std::vector<double>>& node_density,
                                                        const std::vector<FrequencyBand>& nodes, int per_octave,
                                                        const std::vector<FrequencyBand>& bands, std::vector<int>& owner) {
  owner.assign(bands.size(), -1);
  for (std::size_t t = 0; t < bands.size(); ++t) {
    for (std::size_t o = 0; o < nodes.size(); ++o) {
      if (bands[t].center_hz >= nodes[o].lower_hz && bands[t].center_hz < nodes[o].upper_hz) owner[t] = static_cast<int>(o);
    }
  }
  std::vector<std::vector<double>> density(bands.size(), std::vector<double>(node_density.size(), 0.0));
  for (std::size_t t = 0; t < bands.size(); ++t) {
    if (owner[t] < 0) continue;
    const double x = std::clamp(per_octave * std::log2(bands[t].center_hz / nodes.front().center_hz), 0.0,
                                static_cast<double>(nodes.size() - 1));
    const std::size_t i = std::min(static_cast<std::size_t>(x), nodes.size() - 2);
    const double f = x - static_cast<double>(i);
    for (std::size_t bin = 0; bin < node_density.size(); ++bin) {
      const double d0 = node_density[bin][i];
      const double d1 = node_density[bin][i + 1];
      density[t][bin] = (d0 > 0.0 && d1 > 0.0) ? std::exp((1.0 - f) * std::log(d0) + f * std::log(d1)) : (1.0 - f) * d0 + f * d1;
    }
  }
  return density;
}

void addLateField(const BandViews& in, const SynthesisOptions& o, AudioBuffer& out) {
  const EnergyHistogram& first = *in.late.front();
  const std::size_t frames = out.frameCount();
  const std::size_t channels = out.channelCount();
  const int order = static_cast<int>(std::lround(std::sqrt(static_cast<double>(channels)))) - 1;
  const double bin_frames = first.binS() * o.sample_rate_hz;
  const double to_pressure = 4.0 * kPi;  // J/m^2 per emitted J -> energy re the direct sound at 1 m
  const std::vector<FrequencyBand> nodes = viewBands(in.views());
  // Amplitude-complementary bands: bands of one noise, scaled by gains that vary smoothly
  // across the spectrum, sum to noise whose spectrum follows those gains.
  const BandFilterBank bank(lateSynthesisBands(in.views()), o.sample_rate_hz, 0.5, Complementarity::kAmplitude);
  const std::vector<double> bandwidth_hz = noiseBandwidthsHz(bank);

  // Per bin and node band: power spectral density per sample, and per channel the two
  // gains the sample loop applies (flat: [bin][node][channel]): of the main sequence (the
  // direction's harmonic times the square root of the directional fraction) and of the
  // channel's own sequence (the root of the diffuse fraction spread over the order's 2l+1
  // channels). Precomputed here, the loop over samples takes one square root per sample.
  const std::size_t node_count = nodes.size();
  std::vector<std::vector<double>> density(first.bins(), std::vector<double>(node_count, 0.0));
  std::vector<double> directional_gain(first.bins() * node_count * channels);
  std::vector<double> diffuse_gain(first.bins() * node_count * channels);
  const double per_hz = 1.0 / (0.5 * o.sample_rate_hz);
  for (std::size_t bin = 0; bin < first.bins(); ++bin) {
    for (std::size_t t = 0; t < node_count; ++t) {
      const EnergyHistogram& late = *in.late[in.viewOf(t)];
      const int b = in.octaveOf(t);
      const double energy = to_pressure * late.energy(bin, b) / bin_frames;
      density[bin][t] = energy * per_hz;
      const Eigen::Vector3d flux = to_pressure * late.flux(bin, b) / bin_frames;
      const double directional = energy > 0.0 ? std::min(1.0, flux.norm() / energy) : 0.0;
      const std::vector<double> y = sn3dHarmonics(order, flux.norm() > 0.0 ? Eigen::Vector3d(flux.normalized()) : Eigen::Vector3d::UnitX());
      const std::size_t at = (bin * node_count + t) * channels;
      for (std::size_t c = 0; c < channels; ++c) {
        directional_gain[at + c] = y[c] * std::sqrt(directional);
        diffuse_gain[at + c] = std::sqrt((1.0 - directional) / (2.0 * orderOfChannel(c) + 1.0));
      }
    }
  }
  std::vector<int> owner;
  const std::vector<std::vector<double>> targets =
      synthesisBandDensities(density, nodes, static_cast<int>(in.views()), bank.bands(), owner);

  // Channel 0 carries the whole energy and the directional part, the others add the
  // diffuse part, each from its own noise.
  std::vector<bool> wanted(bank.bands().size());
  for (std::size_t t = 0; t < wanted.size(); ++t) wanted[t] = owner[t] >= 0 && bank.bandBelowNyquist(t);
  LateFieldNoiseShape shape;
  shape.seed = o.seed;
  shape.frames = frames;
  shape.channels = channels;
  shape.sample_rate_hz = o.sample_rate_hz;
  shape.room_volume_m3 = o.room_volume_m3;
  shape.speed_of_sound_m_s = o.speed_of_sound_m_s;
  shape.max_event_rate_per_s = o.max_event_rate_per_s;
  shape.bin_frames = bin_frames;
  const std::shared_ptr<const LateFieldNoise> noise = lateFieldNoise(shape, bank, wanted);

  for (std::size_t t = 0; t < bank.bands().size(); ++t) {
    if (!wanted[t]) continue;
    const auto b = static_cast<std::size_t>(owner[t]);
    const std::vector<std::vector<float>>& unit = noise->normalised[t];
    for (std::size_t n = 0; n < frames; ++n) {
      const double position = n / bin_frames;
      // The band's noise has density 1 / bandwidth once normalised; scaled to the target.
      const double target = interpolatedTarget(targets[t], position) * bandwidth_hz[t];
      if (target <= 0.0 || unit[0][n] == 0.0f) continue;
      const auto bin = std::min(first.bins() - 1, static_cast<std::size_t>(position));
      const std::size_t at = (bin * node_count + b) * channels;
      const double amplitude = std::sqrt(target);
      const double main = amplitude * unit[0][n];
      out.channels[0][n] += static_cast<float>(main);
      for (std::size_t c = 1; c < channels; ++c) {
        const double v = main * directional_gain[at + c] + amplitude * diffuse_gain[at + c] * unit[c][n];
        out.channels[c][n] += static_cast<float>(v);
      }
    }
  }
}

}  // namespace

namespace {

AudioBuffer synthesize(const BandViews& in, const SynthesisOptions& options) {
  if (options.ambisonic_order < 0 || options.ambisonic_order > kMaxAmbisonicOrder) {
    throw InputError("ambisonic order must be 0 to 3");
  }
  if (!(options.duration_s > 0.0)) throw InputError("the response duration must be positive");
  if (!(options.room_volume_m3 > 0.0)) throw InputError("the room volume must be positive");
  const auto frames = static_cast<std::size_t>(std::ceil(options.duration_s * options.sample_rate_hz));
  AudioBuffer out = makeSilentBuffer(static_cast<std::size_t>(ambisonicChannelCount(options.ambisonic_order)), frames,
                                     options.sample_rate_hz);
  const BandFilterBank bank(viewBands(in.views()), options.sample_rate_hz);
  addEarlyPaths(in, bank, options.ambisonic_order, out);
  if (in.late.front()) addLateField(in, options, out);
  return out;
}

}  // namespace

AudioBuffer synthesizeImpulseResponse(const std::vector<SpecularPath>& paths, const EnergyHistogram* late,
                                      const SynthesisOptions& options) {
  return synthesize(BandViews{{&paths}, {late}}, options);
}

AudioBuffer synthesizeThirdOctaveImpulseResponse(const std::array<const std::vector<SpecularPath>*, 3>& paths,
                                                 const std::array<const EnergyHistogram*, 3>& late,
                                                 const SynthesisOptions& options) {
  for (std::size_t k = 0; k < 3; ++k) {
    if (!paths[k]) throw std::logic_error("third-octave synthesis: every third needs its paths");
    if ((late[k] == nullptr) != (late[0] == nullptr)) throw std::logic_error("third-octave synthesis: late energy for some thirds only");
    const std::vector<SpecularPath>& a = *paths[0];
    const std::vector<SpecularPath>& b = *paths[k];
    bool same = a.size() == b.size();
    for (std::size_t i = 0; same && i < a.size(); ++i) same = a[i].delay_s == b[i].delay_s && a[i].order == b[i].order;
    if (!same) throw std::logic_error("third-octave synthesis: the thirds' image sources differ in their arrivals");
    if (late[k] && (late[k]->bins() != late[0]->bins() || late[k]->binS() != late[0]->binS())) {
      throw std::logic_error("third-octave synthesis: the thirds' histograms differ in their bins");
    }
  }
  return synthesize(BandViews{{paths[0], paths[1], paths[2]}, {late[0], late[1], late[2]}}, options);
}

}  // namespace room_reverb::core
