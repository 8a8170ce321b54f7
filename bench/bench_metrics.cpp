// Speed of the metrics path: a 3 s measured-length RIR through the octave and
// third-octave analyses, and the FFT convolution it rests on. Run: scripts/bench
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "room_reverb/audio/convolution.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"

namespace {

std::vector<float> decayingNoise(std::size_t length, double t60_s) {
  std::mt19937 rng(1);
  std::normal_distribution<float> normal;
  std::vector<float> x(length);
  const double delta = 6.0 * std::log(10.0) / (t60_s * 48000.0);
  for (std::size_t n = 0; n < length; ++n) x[n] = static_cast<float>(normal(rng) * std::exp(-0.5 * delta * n) + 1e-3 * normal(rng));
  return x;
}

void BM_MetricsOctave3s(benchmark::State& state) {
  const auto rir = decayingNoise(3 * 48000, 1.2);
  for (auto _ : state) benchmark::DoNotOptimize(room_reverb::core::computeRoomAcousticParameters(rir, 48000.0));
}
BENCHMARK(BM_MetricsOctave3s)->Unit(benchmark::kMillisecond);

void BM_MetricsThirdOctave3s(benchmark::State& state) {
  const auto rir = decayingNoise(3 * 48000, 1.2);
  room_reverb::core::MetricsOptions options;
  options.resolution = room_reverb::core::BandResolution::kThirdOctave;
  for (auto _ : state) benchmark::DoNotOptimize(room_reverb::core::computeRoomAcousticParameters(rir, 48000.0, options));
}
BENCHMARK(BM_MetricsThirdOctave3s)->Unit(benchmark::kMillisecond);

void BM_FftConvolve(benchmark::State& state) {
  const auto signal = decayingNoise(static_cast<std::size_t>(state.range(0)), 1.0);
  const auto kernel = decayingNoise(static_cast<std::size_t>(state.range(0)), 0.5);
  for (auto _ : state) benchmark::DoNotOptimize(room_reverb::core::fftConvolve(signal, kernel));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_FftConvolve)->Arg(4096)->Arg(48000)->Arg(144000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
