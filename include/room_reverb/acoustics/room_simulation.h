#pragma once
// One interface, three renderers:
//  - accurate: image sources plus stochastic ray tracing (what Steam Audio's baking does;
//    the paper's accurate route);
//  - fast: image sources plus the late part of fewer rays: where a pilot of 2000 rays
//    shows a diffuse room, the energy they carry through the room over time as a diffuse
//    field; otherwise up to 64 000 rays heard at a track receiver, the track they run
//    within 2 m of the listener (fast_mode_rays.h). It knows where the absorption is: in a
//    room whose absorption sits on the floor and ceiling the decay is what the rays
//    between the hard walls make it, not Eyring's mean (docs/simulation.md);
//  - eyring: image sources plus a parametric tail from Eyring's formula with air
//    absorption (what Resonance Audio does: the paper's fast route, kept to reproduce its
//    listening test).
// Every physical effect is an explicit switch: air (air.enabled), scattering and absorption
// (MaterialOverrides on the scene), source directivity, image-source order, rays.
#include <memory>
#include <optional>
#include <string>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/fast_mode_rays.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/acoustics/impulse_response_synthesis.h"
#include "room_reverb/acoustics/path_ledger.h"
#include "room_reverb/acoustics/ray_tracer.h"
#include "room_reverb/acoustics/wave_low_band.h"

namespace room_reverb::core {

enum class SimulationMode { kFast, kAccurate, kEyring };
SimulationMode parseSimulationMode(const std::string& name);  // "fast" | "accurate" | "eyring"
std::string toString(SimulationMode mode);

struct SimulationSettings {
  SimulationMode mode = SimulationMode::kAccurate;
  int image_source_order = 3;
  double duration_s = 2.0;
  int ambisonic_order = 1;  // 0: omni
  AirConditions air;
  SourceDirectivity directivity;
  RayTracingOptions rays;   // ray count, seed, threads, receiver radius (accurate mode)
  // The most rays of the fast mode's decay (seed and threads from `rays`); `fast_rays`
  // says when fewer will do (fast_mode_rays.h). In BRAS CR2 T20 spreads by 1-2 % over
  // seeds at 2000 rays as at 8000 and the pilot settles; in rooms whose late sound rides
  // on grazing paths the spread is 5-11 % at 8000 and 1-4 % at 64 000 (the carpeted room),
  // and the run takes as many of these as fast_rays.reflection_budget buys.
  std::size_t fast_ray_count = 64000;
  FastRayOptions fast_rays;
  // The scattering of the surfaces' finite size, added to the materials' in the image
  // sources and the rays alike (diffraction_scattering.h; the `rays` option of the same
  // name is set from this one).
  bool diffraction_scattering = false;
  // Below `wave.crossover_hz` the first-order channels from the wave solver instead of
  // the geometric response (wave_low_band.h), in every mode; its threads are `rays`'.
  LowBandMethod low_band = LowBandMethod::kGeometric;
  WaveLowBandOptions wave;
  // Third octaves end to end: the geometric response simulated once per third of every
  // octave with the materials' third-octave coefficients (AcousticScene::thirdOctaveBands;
  // octave values for materials without thirds) and synthesised in 27 thirds, 50 Hz ..
  // 20 kHz; three times the octave mode's cost. The result's paths and late energy are
  // then the octave means of the thirds'.
  BandResolution bands = BandResolution::kOctave;
};

struct SimulationResult {
  AudioBuffer impulse_response;            // ACN/SN3D, 48 kHz; channel 0 is omni
  std::vector<SpecularPath> paths;         // image-source arrivals
  EnergyHistogram late;                    // ray-traced or parametric late energy
  RayTracingStats stats;                   // accurate and fast modes
  OctaveBandValues eyring_t60_s{};         // Eyring with air, for reference
  WaveLowBandStats low_band;               // the wave solver's part, when it was used
  double speed_of_sound_m_s = 0.0;
  // In third octaves (SimulationSettings::bands), the late energy of each third's view
  // (AcousticScene::thirdOctaveBands), from which the response's late part was
  // synthesised; `late` is then their octave mean. Empty in octaves. This process only,
  // never on the wire.
  std::vector<EnergyHistogram> late_thirds;
  // The ray tracer's paths when the caller asked for them (simulateRoom's
  // ledger_budget_bytes) and they could be kept; this process only, never on the wire.
  std::shared_ptr<const PathLedger> ledger;
};

// Throws InputError when the source or listener is outside the room, in an object or too
// close to a wall, or for invalid settings.
// `progress` hears the wave low band's runs (wave_low_band.h), when there are any.
// `ledger_budget_bytes` > 0 keeps the accurate mode's paths in the result (traceRays).
SimulationResult simulateRoom(const AcousticScene& scene, const Eigen::Vector3d& source,
                              const Eigen::Vector3d& listener, const SimulationSettings& settings,
                              const WaveProgress& progress = {}, std::size_t ledger_budget_bytes = 0);

// simulateRoom's answer for a model that differs from `traced`'s only in its absorption,
// its air (at the same speed of sound) or its source directivity, from `traced`'s ledger:
// the image sources found for the new model, the late energy replayed (path_ledger.h), the
// response synthesised with the same seed. Tracing the new model instead gives the same
// result in expectation, with its own noise. nullopt, with the reason in `why_not`, when
// it cannot be replayed (no ledger, other geometry, scattering, positions or settings, or
// too few effective rays); the result then carries the traced paths' ledger for further
// replays.
std::optional<SimulationResult> replaySimulation(const SimulationResult& traced, const AcousticScene& scene,
                                                 const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                                                 const SimulationSettings& settings, std::string& why_not);

// How simulateRoom turns its paths and late energy into the impulse response: the
// synthesis options of the scene and settings (the early and late parts synthesised apart
// with them add up to simulateRoom's response exactly).
SynthesisOptions simulationSynthesisOptions(const AcousticScene& scene, const SimulationSettings& settings);

// The late part of simulateRoom's response alone (its early and late parts synthesised apart
// add up to the response exactly): from the thirds' late energy where the result has it.
AudioBuffer synthesizeLatePart(const SimulationResult& result, const SynthesisOptions& synthesis);

// The image-source search of the settings: their order and diffraction scattering.
ImageSourceOptions imageSourceOptionsFor(const SimulationSettings& settings);

// Eyring's reverberation time with air per octave band, for the scene.
OctaveBandValues eyringReverberationTimes(const AcousticScene& scene, const AirConditions& air);

// The eyring mode's late energy: an exponential decay per band (Eyring with air) whose
// level is that of a diffuse field, c / V per second per J emitted, faded in around the
// time the image sources of `order` run out.
EnergyHistogram parametricLateEnergy(const AcousticScene& scene, const PropagationModel& model,
                                     double direct_delay_s, int order, double duration_s, double bin_s);

// The fast mode's late energy where its pilot settles: a diffuse field of the energy the
// rays carry through the room at each bin less what the image sources' paths carry
// (RayTracingResult::late_energy_in_flight), from the direct sound on with no fade: the
// diffuse energy of the first reflections, which a fade after the image sources leaves
// out, is heard (it sets the EDT). An open room (no enclosed volume) takes its bounding
// box's volume.
EnergyHistogram roomDecayLateEnergy(const AcousticScene& scene, const PropagationModel& model,
                                    const std::vector<OctaveBandValues>& late_energy_in_flight, double direct_delay_s,
                                    double bin_s);

}  // namespace room_reverb::core
