#include "room_reverb/acoustics/wave_low_band.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "room_reverb/acoustics/boundary_admittance.h"
#include "room_reverb/acoustics/fdtd_grid.h"
#include "room_reverb/acoustics/fdtd_solver.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/crossover.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kCrossoverWidthOctaves = 1.0;
// The solver runs this much past the response's end, so the octave filters' ringing at
// the end of the signal (they see it stop) falls outside the response.
constexpr double kTailPaddingS = 0.25;

// A closed room keeps the volume the impulse pushes into it as a static pressure (with
// rigid walls, a pressure that keeps rising: the unit pressure impulse at 1 m is a step of
// volume velocity). The response to a source that gives that volume back slowly, x - x*g
// with g a causal triangle of unit area 0.2 s long, loses it (1 - G is 0 at 0 Hz); done
// twice it loses a rising one too. G, a squared sinc with zeros every 10 Hz, is below
// 0.005 from 44 Hz up (the octave bank's lowest edge), so the bands from 63 Hz keep their
// level within 1 %, and the response stays causal.
std::vector<double> movingAverage(const std::vector<double>& x, std::size_t length) {
  std::vector<double> out(x.size());
  double sum = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sum += x[k];
    if (k >= length) sum -= x[k - length];
    out[k] = sum / static_cast<double>(length);
  }
  return out;
}

std::vector<float> withoutStaticPressure(const std::vector<double>& signal, double sample_rate_hz) {
  const auto length = static_cast<std::size_t>(std::max(1L, std::lround(0.1 * sample_rate_hz)));
  std::vector<double> x = signal;
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<double> slow = movingAverage(movingAverage(x, length), length);
    for (std::size_t k = 0; k < x.size(); ++k) x[k] -= slow[k];
  }
  return std::vector<float>(x.begin(), x.end());
}

// Energy of `signal` in the octave band `band` (power-complementary analysis bank).
double bandEnergy(const std::vector<float>& signal, double sample_rate_hz, std::size_t band) {
  const BandFilterBank bank(standardBands(BandResolution::kOctave), sample_rate_hz);
  double energy = 0.0;
  for (float v : bank.extract(bank.analyse(signal), band)) energy += static_cast<double>(v) * v;
  return energy;
}

}  // namespace

LowBandMethod parseLowBandMethod(const std::string& name) {
  if (name == "geometric") return LowBandMethod::kGeometric;
  if (name == "wave") return LowBandMethod::kWave;
  throw InputError("unknown low-band method '" + name + "' (geometric or wave)");
}

std::string toString(LowBandMethod method) { return method == LowBandMethod::kWave ? "wave" : "geometric"; }

WaveLowBand simulateWaveLowBand(const AcousticScene& scene, const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                                double speed_of_sound_m_s, double duration_s, const WaveLowBandOptions& options,
                                const WaveProgress& progress) {
  if (!(options.crossover_hz >= 63.0 && options.crossover_hz <= 2000.0)) {
    throw InputError("the wave low band's crossover must be 63 to 2000 Hz");
  }
  if (!(options.cells_per_wavelength >= 4.0)) throw InputError("the wave solver needs at least 4 cells per wavelength");
  const auto started = std::chrono::steady_clock::now();
  const double spacing = fdtdSpacingFor(options.crossover_hz, options.cells_per_wavelength, speed_of_sound_m_s);
  const FdtdGrid grid = voxelizeScene(scene, spacing);
  const double top_hz = options.crossover_hz * std::pow(2.0, 0.5 * kCrossoverWidthOctaves);

  // The bands the runs stand for: the octaves, or the thirds of the octaves.
  const bool thirds = options.bands == BandResolution::kThirdOctave;
  const std::vector<FrequencyBand> bands = thirds ? thirdsOfTheOctaves() : standardBands(BandResolution::kOctave);
  const std::size_t per_octave = thirds ? 3 : 1;
  FdtdOptions solver;
  solver.duration_s = duration_s + kTailPaddingS;
  solver.speed_of_sound_m_s = speed_of_sound_m_s;
  solver.threads = options.threads;
  WaveLowBand out;
  out.stats.used = true;
  out.stats.crossover_hz = options.crossover_hz;
  out.stats.grid_spacing_m = spacing;
  out.stats.grid_cells = grid.cellCount();

  // ACN order W, Y, Z, X; the solver's velocity channels are x, y, z.
  constexpr int kVelocityAxis[4] = {-1, 1, 2, 0};
  AudioBuffer sum;
  std::optional<BandFilterBank> bank;
  std::vector<BandFilterBank::PaddedSpectrum> latest(4);
  std::size_t runs = 0;
  for (std::size_t b = 0; b < bands.size(); ++b) runs += (b == 0 || bands[b].center_hz < top_hz) ? 1 : 0;
  auto tell = [&](const std::string& line) {
    if (progress) progress(line);
  };
  for (std::size_t b = 0; b < bands.size(); ++b) {
    if (b == 0 || bands[b].center_hz < top_hz) {
      std::vector<double> admittance;
      for (const AcousticMaterial& material : scene.materials()) {
        const AcousticMaterial band_material =
            thirds ? thirdOctaveMaterial(material, static_cast<int>(b % per_octave)) : material;
        admittance.push_back(admittanceForRandomIncidenceAbsorption(band_material.absorption[b / per_octave]));
      }
      const FdtdResponse response = solveWaveField(grid, source, listener, admittance, solver);
      ++out.stats.solver_runs;
      tell(std::string("wave low band: ") + (thirds ? "third " : "octave ") +
           std::to_string(static_cast<int>(bands[b].nominal_hz)) + " Hz done (" +
           std::to_string(out.stats.solver_runs) + " of " + std::to_string(runs) + " runs on " +
           std::to_string(grid.cellCount()) + " cells, " +
           std::to_string(static_cast<int>(std::lround(
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()))) +
           " s so far)");
      if (!bank) {
        bank.emplace(bands, response.sample_rate_hz, 0.5, Complementarity::kAmplitude);
        sum = makeSilentBuffer(4, response.steps, response.sample_rate_hz);
      }
      for (std::size_t c = 0; c < 4; ++c) {
        const std::vector<double>& channel =
            c == 0 ? response.pressure : response.velocity[static_cast<std::size_t>(kVelocityAxis[c])];
        latest[c] = bank->analyse(withoutStaticPressure(channel, response.sample_rate_hz));
      }
    }
    if (!bank->bandBelowNyquist(b)) continue;
    // This band from its own run, or, above the last run, from the last.
    for (std::size_t c = 0; c < 4; ++c) {
      const std::vector<float> part = bank->extract(latest[c], b);
      for (std::size_t n = 0; n < part.size(); ++n) sum.channels[c][n] += part[n];
    }
  }
  // The solver's rate (17.3 times the crossover: 4.3 kHz at 250 Hz) can lie below what
  // the resampler accepts (8 kHz); a sinc converter depends only on the ratio, so both
  // rates are scaled by the same whole number.
  const double scale = std::ceil(8000.0 / sum.sample_rate_hz);
  sum.sample_rate_hz *= scale;
  out.response = resample(sum, kInternalSampleRateHz * scale);
  out.response.sample_rate_hz = kInternalSampleRateHz;
  const auto frames = static_cast<std::size_t>(std::lround(duration_s * kInternalSampleRateHz));
  for (auto& channel : out.response.channels) channel.resize(std::min(channel.size(), frames));
  // The solver's response has unit area per 1/r; a 48 kHz tap of the image sources has
  // gain 1/r in one sample.
  for (auto& channel : out.response.channels) {
    for (float& v : channel) v = static_cast<float>(v / kInternalSampleRateHz);
  }
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return out;
}

AudioBuffer joinWaveLowBand(const WaveLowBand& wave, const AudioBuffer& geometric, WaveLowBandStats& stats) {
  stats = wave.stats;
  const AudioBuffer joined = joinAtCrossover(wave.response, geometric, wave.stats.crossover_hz, kCrossoverWidthOctaves);
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  std::size_t band = 0;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    if (std::abs(std::log2(bands[b].center_hz / wave.stats.crossover_hz)) <
        std::abs(std::log2(bands[band].center_hz / wave.stats.crossover_hz))) {
      band = b;
    }
  }
  const double wave_energy = bandEnergy(wave.response.channels[0], wave.response.sample_rate_hz, band);
  const double geometric_energy = bandEnergy(geometric.channels[0], geometric.sample_rate_hz, band);
  stats.overlap_level_db = wave_energy > 0.0 && geometric_energy > 0.0 ? 10.0 * std::log10(wave_energy / geometric_energy) : 0.0;
  return joined;
}

}  // namespace room_reverb::core
