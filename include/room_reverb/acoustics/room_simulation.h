#pragma once
// One interface, two renderers (the paper's two simulation routes):
//  - fast: image sources plus a parametric late tail from Eyring's formula with air
//    absorption (what Resonance Audio does), for previews and small targets;
//  - accurate: image sources plus stochastic ray tracing (what Steam Audio's baking does).
// Every physical effect is an explicit switch: air (air.enabled), scattering and absorption
// (MaterialOverrides on the scene), source directivity, image-source order, rays.
#include <string>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/acoustics/impulse_response_synthesis.h"
#include "room_reverb/acoustics/ray_tracer.h"

namespace room_reverb::core {

enum class SimulationMode { kFast, kAccurate };
SimulationMode parseSimulationMode(const std::string& name);  // "fast" | "accurate"
std::string toString(SimulationMode mode);

struct SimulationSettings {
  SimulationMode mode = SimulationMode::kAccurate;
  int image_source_order = 3;
  double duration_s = 2.0;
  int ambisonic_order = 1;  // 0: omni
  AirConditions air;
  SourceDirectivity directivity;
  RayTracingOptions rays;   // ray count, seed, threads, receiver radius (accurate mode)
};

struct SimulationResult {
  AudioBuffer impulse_response;            // ACN/SN3D, 48 kHz; channel 0 is omni
  std::vector<SpecularPath> paths;         // image-source arrivals
  EnergyHistogram late;                    // ray-traced or parametric late energy
  RayTracingStats stats;                   // accurate mode
  OctaveBandValues eyring_t60_s{};         // Eyring with air, for reference
  double speed_of_sound_m_s = 0.0;
};

// Throws InputError when the source or listener is outside the room, in an object or too
// close to a wall, or for invalid settings.
SimulationResult simulateRoom(const AcousticScene& scene, const Eigen::Vector3d& source,
                              const Eigen::Vector3d& listener, const SimulationSettings& settings);

// Eyring's reverberation time with air per octave band, for the scene.
OctaveBandValues eyringReverberationTimes(const AcousticScene& scene, const AirConditions& air);

// The fast mode's late energy: an exponential decay per band (Eyring with air) whose
// level is that of a diffuse field, c / V per second per J emitted, faded in around the
// time the image sources of `order` run out.
EnergyHistogram parametricLateEnergy(const AcousticScene& scene, const PropagationModel& model,
                                     double direct_delay_s, int order, double duration_s, double bin_s);

}  // namespace room_reverb::core
