#include "room_reverb/evaluation/simulated_pairs.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <thread>

#include "room_reverb/metrics/impulse_response_metrics.h"

namespace room_reverb::core {

std::uint32_t pairSeed(std::uint32_t base_seed, std::size_t pair) {
  return base_seed + static_cast<std::uint32_t>(pair);
}

void runPairsInRounds(std::size_t count, int threads, const std::function<void(std::size_t, int)>& job) {
  const std::size_t workers =
      static_cast<std::size_t>(threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::exception_ptr> failures(count);
  for (std::size_t first = 0; first < count; first += workers) {
    const std::size_t in_round = std::min(workers, count - first);
    const int each = static_cast<int>(std::max<std::size_t>(1, workers / in_round));
    auto run = [&](std::size_t i) {
      try {
        job(i, each);
      } catch (...) {
        failures[i] = std::current_exception();
      }
    };
    std::vector<std::thread> pool;
    for (std::size_t i = first + 1; i < first + in_round; ++i) pool.emplace_back(run, i);
    run(first);
    for (std::thread& t : pool) t.join();
  }
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
}

std::vector<SimulatedPair> simulatePairs(const AcousticScene& scene, const std::vector<MeasurementPair>& pairs,
                                         const SimulationSettings& settings, BandResolution resolution,
                                         const std::function<void(std::size_t, const SimulatedPair&)>& progress) {
  std::vector<SimulatedPair> out(pairs.size());
  runPairsInRounds(pairs.size(), settings.rays.threads, [&](std::size_t i, int threads) {
    const auto start = std::chrono::steady_clock::now();
    SimulationSettings pair_settings = settings;
    pair_settings.rays.seed = pairSeed(settings.rays.seed, i);
    pair_settings.rays.threads = threads;
    const SimulationResult result = simulateRoom(scene, pairs[i].source_m, pairs[i].receiver_m, pair_settings);
    MetricsOptions options;
    options.resolution = resolution;
    out[i].metrics = analyseImpulseResponse(result.impulse_response, 0, options);
    out[i].stats = result.stats;
    out[i].wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  });
  if (progress) {
    for (std::size_t i = 0; i < out.size(); ++i) progress(i, out[i]);
  }
  return out;
}

}  // namespace room_reverb::core
