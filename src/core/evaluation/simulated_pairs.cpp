#include "room_reverb/evaluation/simulated_pairs.h"

#include <chrono>

#include "room_reverb/metrics/impulse_response_metrics.h"

namespace room_reverb::core {

std::uint32_t pairSeed(std::uint32_t base_seed, std::size_t pair) {
  return base_seed + static_cast<std::uint32_t>(pair);
}

std::vector<SimulatedPair> simulatePairs(const AcousticScene& scene, const std::vector<MeasurementPair>& pairs,
                                         const SimulationSettings& settings, BandResolution resolution,
                                         const std::function<void(std::size_t, const SimulatedPair&)>& progress) {
  std::vector<SimulatedPair> out;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    SimulationSettings pair_settings = settings;
    pair_settings.rays.seed = pairSeed(settings.rays.seed, i);
    const SimulationResult result = simulateRoom(scene, pairs[i].source_m, pairs[i].receiver_m, pair_settings);
    MetricsOptions options;
    options.resolution = resolution;
    SimulatedPair pair;
    pair.metrics = analyseImpulseResponse(result.impulse_response, 0, options);
    pair.stats = result.stats;
    pair.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.push_back(pair);
    if (progress) progress(i, out.back());
  }
  return out;
}

}  // namespace room_reverb::core
