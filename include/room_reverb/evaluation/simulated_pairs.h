#pragma once
// Simulating every source-receiver pair of a measurement and analysing each simulated
// RIR exactly as the metrics module analyses a measured one.
#include <cstdint>
#include <functional>
#include <vector>

#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/acoustics/simulation_runner.h"
#include "room_reverb/common/parallel_rounds.h"
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

// The simulation of every pair: pair i with pairSeed(settings.rays.seed, i) and the thread
// count runInRounds gives it for settings.rays.threads, so that its result is the same
// wherever a runner runs it.
std::vector<SimulationRequest> pairRequests(const std::vector<MeasurementPair>& pairs, const SimulationSettings& settings);

// The requests' results from `runner`, or, when there is none, in this process, `threads`
// at a time (0: all hardware threads). `wall_times_s` (may be null): as SimulationRunner's.
std::vector<SimulationResult> runSimulations(const AcousticScene& scene, const std::vector<SimulationRequest>& requests,
                                             int threads, SimulationRunner* runner,
                                             std::vector<double>* wall_times_s = nullptr);

// Pair i is simulated as pairRequests says, by `runner` (null: this process, in rounds of
// settings.rays.threads), and analysed here. `progress` (may be empty) is called on the
// calling thread with each pair's index, in order, once every pair has been simulated.
std::vector<SimulatedPair> simulatePairs(const AcousticScene& scene, const std::vector<MeasurementPair>& pairs,
                                         const SimulationSettings& settings, BandResolution resolution,
                                         const std::function<void(std::size_t, const SimulatedPair&)>& progress = {},
                                         SimulationRunner* runner = nullptr);

}  // namespace room_reverb::core
