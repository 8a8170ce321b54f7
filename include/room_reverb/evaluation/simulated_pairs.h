#pragma once
// Simulating every source-receiver pair of a measurement and analysing each simulated
// RIR exactly as the metrics module analyses a measured one.
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

// Pair i is simulated with seed settings.rays.seed + i, so pairs do not share their noise.
// `progress` (may be empty) is called after each pair with its index.
std::vector<SimulatedPair> simulatePairs(const AcousticScene& scene, const std::vector<MeasurementPair>& pairs,
                                         const SimulationSettings& settings, BandResolution resolution,
                                         const std::function<void(std::size_t, const SimulatedPair&)>& progress = {});

}  // namespace room_reverb::core
