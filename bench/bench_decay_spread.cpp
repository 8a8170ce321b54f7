// How much the simulated decay time of the demo's sample room scatters from one ray-tracing
// seed to the next, and whether more rays lower it (docs/validation/diagnosis.md). The
// diagnosis must stand clear of this scatter: it sets the noise of every held-out error.
// The model is what the cameras see (data/sample_room/visible.yaml: hard walls that
// scatter 5 %, an absorbing floor and ceiling), at the demo's source and listener, omni.
// Per band, twelve seeds: the coefficient of variation of T20 read from the synthesised
// response (cv_<band>, %) and from the ray-traced late energy itself (hist_cv_<band>, %:
// the Schroeder curve of the histogram, -5 to -25 dB; no noise synthesis), and the
// mean T20 at 1 kHz. A Monte Carlo spread would halve for each fourfold rise in rays.
// Each ray count runs with the automatic detection sphere (radius_cm 0, sized for a fixed
// count of crossings, so it shrinks as the rays rise) and with fixed 0.5 m and 1.26 m
// spheres (1.26 m: the listener's clearance), which tell the sphere's share of the spread
// from the rays' (docs/validation/diagnosis.md).
// Run: .ws/devel/lib/room_reverb/bench_decay_spread (about 4 minutes on 2 cores).
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/common/sample_statistics.h"
#include "room_reverb/diagnosis/diagnosis_setup.h"
#include "room_reverb/metrics/energy_decay.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"

namespace {

using namespace room_reverb::core;

constexpr int kSeeds = 12;
const std::vector<double> kBandsHz{250, 500, 1000, 2000};

double coefficientOfVariationPercent(const std::vector<double>& v) {
  return 100.0 * sampleStandardDeviation(v) / sampleMean(v);
}

// T20 of one band of the late histogram, by the same Schroeder-curve fit as a response's
// (EnergyDecay): the bins' energies are the squared "signal" at one sample per bin.
double histogramT20(const EnergyHistogram& late, int band) {
  std::vector<float> amplitude(late.bins());
  for (std::size_t k = 0; k < late.bins(); ++k) amplitude[k] = static_cast<float>(std::sqrt(late.energy(k, band)));
  return EnergyDecay(amplitude, 0, 1.0 / late.binS()).decayTimeS(-5.0, -25.0);
}

int octaveIndex(double nominal_hz) {
  const std::vector<FrequencyBand> octaves = standardBands(BandResolution::kOctave);
  for (std::size_t b = 0; b < octaves.size(); ++b) {
    if (octaves[b].nominal_hz == nominal_hz) return static_cast<int>(b);
  }
  return -1;
}

void BM_SampleRoomT20SpreadOverSeeds(benchmark::State& state) {
  const std::string dir = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/sample_room/";
  const RoomUnderTest model = RoomUnderTest::fromRoomModel(loadRoomModel(dir + "visible.yaml"), MaterialLibrary::loadDefault());
  const AcousticScene scene = model.scene({});
  SimulationSettings s;
  s.duration_s = 1.5;
  s.ambisonic_order = 0;
  s.air = model.air();
  s.rays.ray_count = static_cast<std::size_t>(state.range(0));
  s.rays.receiver_radius_m = static_cast<double>(state.range(1)) / 100.0;  // 0: automatic
  double last_radius_m = 0.0;
  std::vector<std::vector<double>> rir_t20(kBandsHz.size()), hist_t20(kBandsHz.size());
  for (auto _ : state) {
    for (int seed = 1; seed <= kSeeds; ++seed) {
      s.rays.seed = static_cast<std::uint32_t>(seed);
      const SimulationResult r = simulateRoom(scene, Eigen::Vector3d(4.6, 2.9, 1.5), Eigen::Vector3d(2.7, 2.1, 1.4), s);
      last_radius_m = r.stats.receiver_radius_m;
      const MetricsReport m = computeRoomAcousticParameters(r.impulse_response.channels[0], 48000.0);
      for (std::size_t i = 0; i < kBandsHz.size(); ++i) {
        hist_t20[i].push_back(histogramT20(r.late, octaveIndex(kBandsHz[i])));
        for (const AcousticParameters& band : m.bands) {
          if (band.nominal_hz == kBandsHz[i] && band.t20_s) rir_t20[i].push_back(*band.t20_s);
        }
      }
    }
  }
  for (std::size_t i = 0; i < kBandsHz.size(); ++i) {
    const std::string hz = std::to_string(static_cast<int>(kBandsHz[i]));
    state.counters["cv_" + hz] = coefficientOfVariationPercent(rir_t20[i]);
    state.counters["hist_cv_" + hz] = coefficientOfVariationPercent(hist_t20[i]);
  }
  double mean_1k = 0.0;
  for (double t : rir_t20[2]) mean_1k += t / static_cast<double>(rir_t20[2].size());
  state.counters["t20_1000_s"] = mean_1k;
  state.counters["radius_m"] = last_radius_m;
}
BENCHMARK(BM_SampleRoomT20SpreadOverSeeds)->ArgNames({"rays", "radius_cm"})->ArgsProduct({{10000, 40000, 160000}, {0, 50, 126}})->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
