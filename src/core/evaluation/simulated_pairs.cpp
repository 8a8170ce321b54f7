#include "room_reverb/evaluation/simulated_pairs.h"

#include <chrono>

#include "room_reverb/metrics/impulse_response_metrics.h"

namespace room_reverb::core {

std::uint32_t pairSeed(std::uint32_t base_seed, std::size_t pair) {
  return base_seed + static_cast<std::uint32_t>(pair);
}

std::vector<SimulationRequest> pairRequests(const std::vector<MeasurementPair>& pairs, const SimulationSettings& settings) {
  std::vector<SimulationRequest> requests(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    requests[i].source_m = pairs[i].source_m;
    requests[i].listener_m = pairs[i].receiver_m;
    requests[i].settings = settings;
    requests[i].settings.rays.seed = pairSeed(settings.rays.seed, i);
    requests[i].settings.rays.threads = roundThreads(pairs.size(), settings.rays.threads, i);
  }
  return requests;
}

std::vector<SimulationResult> runSimulations(const AcousticScene& scene, const std::vector<SimulationRequest>& requests,
                                             int threads, SimulationRunner* runner, std::vector<double>* wall_times_s) {
  if (runner) return runner->simulate(scene, requests, wall_times_s);
  InProcessSimulationRunner here(roundThreads(1, threads, 0));  // 0: every hardware thread
  return here.simulate(scene, requests, wall_times_s);
}

std::vector<SimulatedPair> simulatePairs(const AcousticScene& scene, const std::vector<MeasurementPair>& pairs,
                                         const SimulationSettings& settings, BandResolution resolution,
                                         const std::function<void(std::size_t, const SimulatedPair&)>& progress,
                                         SimulationRunner* runner) {
  std::vector<double> times;
  std::vector<SimulationResult> results =
      runSimulations(scene, pairRequests(pairs, settings), settings.rays.threads, runner, &times);
  std::vector<SimulatedPair> out(pairs.size());
  runInRounds(pairs.size(), settings.rays.threads, [&](std::size_t i, int) {
    const auto start = std::chrono::steady_clock::now();
    MetricsOptions options;
    options.resolution = resolution;
    out[i].metrics = analyseImpulseResponse(results[i].impulse_response, 0, options);
    out[i].stats = results[i].stats;
    out[i].wall_time_s = times[i] + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    results[i] = SimulationResult{};  // its memory back before the next analyses
  });
  if (progress) {
    for (std::size_t i = 0; i < out.size(); ++i) progress(i, out[i]);
  }
  return out;
}

}  // namespace room_reverb::core
