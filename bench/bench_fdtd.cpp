// Speed of the wave solver (acoustics/fdtd_solver.h) on the BRAS CR2 room against the
// memory bandwidth of the same machine in the same run:
//  - BM_FdtdCr2: the leapfrog scheme on CR2's grid for the band up to 500 Hz at 10 cells
//    per wavelength (0.1 s of response), on 1 and 2 threads: grid-cell updates per second;
//  - BM_StreamCopy: a copy of the scheme's two pressure arrays' size (STREAM's "copy"), on
//    1 and 2 threads: bytes moved per second. One cell update moves at least 13 bytes
//    (read the current pressure, read and write the previous one, read the air mask), so
//    bandwidth / 13 is the updates per second memory allows.
//  - BM_VoxelizeCr2: building the grid.
// Run: scripts/bench, or this binary alone (about 20 s). Needs the repository's data.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstring>
#include <thread>
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/boundary_admittance.h"
#include "room_reverb/acoustics/fdtd_grid.h"
#include "room_reverb/acoustics/fdtd_solver.h"
#include "bras_cr2_scene.h"

namespace {

using namespace room_reverb::core;

using room_reverb::bench::cr2Scene;
constexpr double kSpeedOfSound = 343.0;

double cr2Spacing() { return fdtdSpacingFor(500.0, 10.0, kSpeedOfSound); }

void BM_VoxelizeCr2(benchmark::State& state) {
  const AcousticScene* scene = cr2Scene(state);
  if (!scene) return;
  std::size_t cells = 0;
  for (auto _ : state) {
    const FdtdGrid grid = voxelizeScene(*scene, cr2Spacing());
    cells = grid.cellCount();
    benchmark::DoNotOptimize(grid.air.data());
  }
  state.counters["cells"] = static_cast<double>(cells);
}
BENCHMARK(BM_VoxelizeCr2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

void BM_FdtdCr2(benchmark::State& state) {
  const AcousticScene* scene = cr2Scene(state);
  if (!scene) return;
  static const FdtdGrid grid = voxelizeScene(*scene, cr2Spacing());
  std::vector<double> admittance;
  for (const AcousticMaterial& material : scene->materials()) {
    admittance.push_back(admittanceForRandomIncidenceAbsorption(material.absorption[1]));  // 125 Hz
  }
  FdtdOptions options;
  options.duration_s = 0.1;
  options.speed_of_sound_m_s = kSpeedOfSound;
  options.threads = static_cast<int>(state.range(0));
  std::size_t steps = 0;
  for (auto _ : state) {
    const FdtdResponse response = solveWaveField(grid, room_reverb::bench::kCr2Source, room_reverb::bench::kCr2Receiver, admittance, options);
    steps = response.steps;
    benchmark::DoNotOptimize(response.pressure.data());
  }
  state.counters["cells"] = static_cast<double>(grid.cellCount());
  state.counters["air_cells"] = static_cast<double>(grid.airCellCount());
  state.counters["cell_updates_per_s"] =
      benchmark::Counter(static_cast<double>(grid.cellCount() * steps), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FdtdCr2)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

void BM_StreamCopy(benchmark::State& state) {
  // Two arrays of CR2's cell count, far larger than the caches either way.
  const std::size_t n = 8u << 20;
  std::vector<float> a(n, 1.0f), b(n, 0.0f);
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) {
      pool.emplace_back([&, t] {
        const std::size_t lo = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(threads);
        const std::size_t hi = n * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(threads);
        std::memcpy(b.data() + lo, a.data() + lo, (hi - lo) * sizeof(float));
      });
    }
    for (std::thread& thread : pool) thread.join();
    benchmark::DoNotOptimize(b.data());
    benchmark::ClobberMemory();
  }
  // A copy reads and writes every byte.
  state.counters["bytes_per_s"] =
      benchmark::Counter(static_cast<double>(2 * n * sizeof(float)), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_StreamCopy)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
