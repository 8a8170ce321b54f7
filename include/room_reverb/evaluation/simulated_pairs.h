#pragma once
// Simulating every source-receiver pair of a measurement and analysing each simulated
// RIR exactly as the metrics module analyses a measured one.
#include <cstdint>
#include <functional>
#include <vector>

#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"

namespace room_reverb::core {

struct SimulatedPair {
  MetricsReport metrics;       // of the omni (W) channel, at the requested resolution
  RayTracingStats stats;
  double wall_time_s = 0.0;    // simulation and analysis
};

// Pair i of a measurement is simulated with seed base + i, so pairs do not share their
// noise; every simulation of measured pairs (compare, the diagnosis) follows this rule.
std::uint32_t pairSeed(std::uint32_t base_seed, std::size_t pair);

// Calls job(i, threads_of_i) for every pair i in [0, count): up to `threads` pairs at once
// (0: all hardware threads), in rounds; each pair of a full round gets one thread and the
// pairs of a last, smaller round share the threads (the tracer parallelises within a
// simulation, the analysis of a response does not). Which thread count a pair gets
// depends only on i, count and threads, so results are reproducible. The first exception
// (lowest i) of a job is rethrown after every job has ended.
void runPairsInRounds(std::size_t count, int threads, const std::function<void(std::size_t, int)>& job);

// Pair i is simulated with pairSeed(settings.rays.seed, i), in rounds (runPairsInRounds)
// with settings.rays.threads. `progress` (may be empty) is called on the calling thread
// with each pair's index, in order, once every pair has been simulated.
std::vector<SimulatedPair> simulatePairs(const AcousticScene& scene, const std::vector<MeasurementPair>& pairs,
                                         const SimulationSettings& settings, BandResolution resolution,
                                         const std::function<void(std::size_t, const SimulatedPair&)>& progress = {});

}  // namespace room_reverb::core
