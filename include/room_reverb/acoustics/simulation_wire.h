#pragma once
// A simulation as bytes, and its result as bytes: how simulations cross to another
// process or machine (simulation_runner.h: local worker processes; the room_simulator
// node's simulate_job service). A job is the scene (its mesh, each material as resolved
// with the overrides applied, whether it is closed, and the room shape it was built from)
// with one request (source, listener, every setting). Decoded, it is simulated exactly as
// in the calling process: the same scene, the same settings, the same seed and thread
// count, so the result is the same to the last bit (the ray tracer's sum over threads
// depends on their count, which is why a request carries a fixed one).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "room_reverb/acoustics/room_simulation.h"

namespace room_reverb::core {

struct SimulationRequest {
  Eigen::Vector3d source_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d listener_m = Eigen::Vector3d::Zero();
  SimulationSettings settings;  // settings.rays.threads: a fixed count, not 0
};

// Every decoder throws InputError, naming what it decodes, for bytes that are truncated,
// corrupt, from another version, or that describe an invalid scene.
std::vector<std::uint8_t> encodeScene(const AcousticScene& scene);
std::unique_ptr<AcousticScene> decodeScene(const std::uint8_t* data, std::size_t size);

std::vector<std::uint8_t> encodeRequest(const SimulationRequest& request);
SimulationRequest decodeRequest(const std::uint8_t* data, std::size_t size);

std::vector<std::uint8_t> encodeResult(const SimulationResult& result);
SimulationResult decodeResult(const std::uint8_t* data, std::size_t size);

// A job: an encoded scene and a request in one buffer.
std::vector<std::uint8_t> encodeJob(const std::vector<std::uint8_t>& scene_bytes, const SimulationRequest& request);

// A job's parts: its encoded scene (a view into the job's bytes) and its request.
struct JobParts {
  const std::uint8_t* scene = nullptr;
  std::size_t scene_size = 0;
  SimulationRequest request;
};
JobParts splitJob(const std::uint8_t* data, std::size_t size);

}  // namespace room_reverb::core
