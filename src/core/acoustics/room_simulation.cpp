#include "room_reverb/acoustics/room_simulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

SimulationMode parseSimulationMode(const std::string& name) {
  if (name == "fast") return SimulationMode::kFast;
  if (name == "accurate") return SimulationMode::kAccurate;
  if (name == "eyring") return SimulationMode::kEyring;
  throw InputError("unknown simulation mode '" + name + "' (use accurate, fast or eyring)");
}

std::string toString(SimulationMode mode) {
  switch (mode) {
    case SimulationMode::kFast: return "fast";
    case SimulationMode::kEyring: return "eyring";
    case SimulationMode::kAccurate: break;
  }
  return "accurate";
}

OctaveBandValues eyringReverberationTimes(const AcousticScene& scene, const AirConditions& air) {
  const OctaveBandValues alpha = scene.meanAbsorption();
  const OctaveBandValues m = airEnergyAttenuationPerM(air, scene.bandCentresHz());
  OctaveBandValues t60{};
  // An open or leaky mesh encloses no volume: no diffuse-field reverberation time.
  if (!(scene.volumeM3() > 0.0) || !scene.closed()) {
    t60.fill(std::numeric_limits<double>::infinity());
    return t60;
  }
  for (int b = 0; b < kOctaveBandCount; ++b) {
    t60[b] = eyringReverberationTimeS(scene.volumeM3(), scene.surfaceM2(), alpha[b], m[b]);
  }
  return t60;
}

namespace {

// A diffuse field holding energy(t, b) joules (per J emitted) in `volume_m3`, as the
// energy arriving at a receiver per bin: density energy / V times c per unit area and
// time, from `start_s` on, faded in with a raised cosine over `fade_s` (0: at once).
template <typename EnergyAt>
EnergyHistogram diffuseLateField(double volume_m3, double speed_of_sound_m_s, double start_s, double fade_s,
                                 std::size_t bins, double bin_s, EnergyAt energy) {
  EnergyHistogram histogram(bin_s, bins);
  const double c = speed_of_sound_m_s;
  for (std::size_t bin = 0; bin < bins; ++bin) {
    const double t = (bin + 0.5) * bin_s;
    double weight = 1.0;
    if (t <= start_s) continue;
    if (t < start_s + fade_s) weight = 0.5 - 0.5 * std::cos(kPi * (t - start_s) / fade_s);
    for (int b = 0; b < kOctaveBandCount; ++b) {
      const double e = energy(bin, t, b);
      if (e > 0.0) histogram.add(t, b, weight * c / volume_m3 * e * bin_s, Eigen::Vector3d::Zero());
    }
  }
  return histogram;
}

// The volume a diffuse field fills: the enclosed one, or for an open mesh its bounding box's.
double diffuseVolumeM3(const AcousticScene& scene) {
  if (scene.volumeM3() > 0.0 && scene.closed()) return scene.volumeM3();
  if (scene.mesh().vertices.empty()) return 0.0;
  return (scene.geometry().boundsMax() - scene.geometry().boundsMin()).prod();
}

}  // namespace

EnergyHistogram parametricLateEnergy(const AcousticScene& scene, const PropagationModel& model,
                                     double direct_delay_s, int order, double duration_s, double bin_s) {
  const auto bins = static_cast<std::size_t>(std::ceil(duration_s / bin_s));
  const OctaveBandValues t60 = eyringReverberationTimes(scene, model.air);
  // The image sources hold the first `order` reflections; the field takes over after them
  // with a fade one mean free time wide.
  const double mean_free_time = 4.0 * scene.volumeM3() / (scene.surfaceM2() * model.speed_of_sound_m_s);
  return diffuseLateField(scene.volumeM3(), model.speed_of_sound_m_s, direct_delay_s + std::max(0, order) * mean_free_time,
                          mean_free_time, bins, bin_s, [&](std::size_t, double t, int b) {
                            if (!std::isfinite(t60[b])) return 0.0;
                            return std::exp(-6.0 * std::log(10.0) / t60[b] * t);
                          });
}

EnergyHistogram roomDecayLateEnergy(const AcousticScene& scene, const PropagationModel& model,
                                    const std::vector<OctaveBandValues>& late_energy_in_flight, double direct_delay_s,
                                    double bin_s) {
  const double volume = diffuseVolumeM3(scene);
  if (!(volume > 0.0)) return EnergyHistogram(bin_s, late_energy_in_flight.size());
  return diffuseLateField(volume, model.speed_of_sound_m_s, direct_delay_s, 0.0, late_energy_in_flight.size(), bin_s,
                          [&](std::size_t bin, double, int b) { return late_energy_in_flight[bin][b]; });
}

namespace {

// What one set of bands contributes: the image sources and the late energy of the scene
// (octaves, or one third-octave view) in the mode of `settings`.
struct BandsSimulation {
  std::vector<SpecularPath> paths;
  EnergyHistogram late;
  RayTracingStats stats;
  std::shared_ptr<const PathLedger> ledger;
};

BandsSimulation simulateBands(const AcousticScene& scene, const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                              const SimulationSettings& settings, std::size_t ledger_budget_bytes) {
  const PropagationModel model = PropagationModel::from(settings.air, settings.directivity, scene.bandCentresHz());
  BandsSimulation out;
  out.paths = computeImageSources(scene, source, listener, model, imageSourceOptionsFor(settings));
  if (settings.mode == SimulationMode::kAccurate) {
    RayTracingOptions rays = settings.rays;
    rays.max_time_s = settings.duration_s;
    rays.diffraction_scattering = settings.diffraction_scattering;
    rays.image_source_order = settings.image_source_order;
    RayTracingResult traced = traceRays(scene, source, listener, model, rays, ledger_budget_bytes);
    out.late = std::move(traced.histogram);
    out.stats = traced.stats;
    out.ledger = std::move(traced.ledger);
  } else if (settings.mode == SimulationMode::kFast) {
    RayTracingOptions rays = settings.rays;
    rays.max_time_s = settings.duration_s;
    rays.diffraction_scattering = settings.diffraction_scattering;
    rays.record_energy_in_flight = true;
    rays.diffuse_rain = false;  // the receiver's share is not used: only the energy in flight
    // Faded rays play roulette from 40 dB down rather than 60: on BRAS CR2 that takes 40 %
    // off the time with T20, T30 and EDT unchanged to 0.1 % (docs/simulation.md); only
    // the tail below -40 dB, which no decay measure reads, gets noisier.
    rays.roulette_db = std::max(rays.roulette_db, -40.0);
    const FastModeTrace traced =
        traceFastModeDecay(scene, source, listener, model, rays, settings.fast_ray_count, settings.fast_rays);
    out.stats = traced.stats;
    const double direct_delay = (source - listener).norm() / model.speed_of_sound_m_s;
    // A settled pilot says the room's decay is one diffuse field; otherwise the track
    // receiver near the listener is heard (fast_mode_rays.h).
    out.late = traced.receiver ? *traced.receiver
                               : roomDecayLateEnergy(scene, model, traced.late_energy_in_flight, direct_delay,
                                                     rays.bin_s);
  } else {
    const double direct_delay = (source - listener).norm() / model.speed_of_sound_m_s;
    out.late = parametricLateEnergy(scene, model, direct_delay, settings.image_source_order, settings.duration_s,
                                    settings.rays.bin_s);
  }
  return out;
}

// The octave summary of a simulation in third octaves (SimulationResult::paths and late):
// per octave the mean of its thirds' energies, as a white source shares them.
BandsSimulation octaveSummary(const std::array<BandsSimulation, 3>& thirds) {
  BandsSimulation out;
  out.paths = thirds[1].paths;
  for (std::size_t i = 0; i < out.paths.size(); ++i) {
    for (int b = 0; b < kOctaveBandCount; ++b) {
      double power = 0.0;
      for (const BandsSimulation& t : thirds) power += t.paths[i].pressure_gain[b] * t.paths[i].pressure_gain[b];
      out.paths[i].pressure_gain[b] = std::sqrt(power / 3.0);
    }
  }
  out.late = thirds[1].late;
  for (std::size_t bin = 0; bin < out.late.bins(); ++bin) {
    for (int b = 0; b < kOctaveBandCount; ++b) {
      double energy = 0.0;
      Eigen::Vector3d flux = Eigen::Vector3d::Zero();
      for (const BandsSimulation& t : thirds) {
        energy += t.late.energy(bin, b) / 3.0;
        flux += t.late.flux(bin, b) / 3.0;
      }
      out.late.set(bin, b, energy, flux);
    }
  }
  // Counts over all three runs; the per-band figures of the centre thirds.
  out.stats = thirds[1].stats;
  for (std::size_t k : {0u, 2u}) {
    const RayTracingStats& t = thirds[k].stats;
    out.stats.rays += t.rays;
    out.stats.reflections += t.reflections;
    out.stats.leaked_rays += t.leaked_rays;
    out.stats.escaped_rays += t.escaped_rays;
    out.stats.stopped_by_time += t.stopped_by_time;
    out.stats.stopped_by_energy += t.stopped_by_energy;
    out.stats.sphere_detections += t.sphere_detections;
  }
  return out;
}

}  // namespace

SimulationResult simulateRoom(const AcousticScene& scene, const Eigen::Vector3d& source,
                              const Eigen::Vector3d& listener, const SimulationSettings& settings,
                              const WaveProgress& progress, std::size_t ledger_budget_bytes) {
  if (settings.image_source_order < 0) throw InputError("the image-source order must be 0 or more");
  if (!(settings.duration_s > 0.0 && settings.duration_s <= 30.0)) throw InputError("the response duration must be in (0, 30] s");
  scene.requireInside(source, "source");
  scene.requireInside(listener, "listener");
  if ((source - listener).norm() < 0.05) throw InputError("source and listener are closer than 5 cm");

  const PropagationModel model = PropagationModel::from(settings.air, settings.directivity);
  // The wave part first: a position its grid cannot take is refused before the rays run.
  std::optional<WaveLowBand> low;
  if (settings.low_band == LowBandMethod::kWave) {
    WaveLowBandOptions wave = settings.wave;
    wave.threads = settings.rays.threads;
    wave.bands = settings.bands;
    low = simulateWaveLowBand(scene, source, listener, model.speed_of_sound_m_s, settings.duration_s, wave, progress);
  }
  SimulationResult result;
  result.speed_of_sound_m_s = model.speed_of_sound_m_s;
  result.eyring_t60_s = eyringReverberationTimes(scene, settings.air);
  const SynthesisOptions synthesis = simulationSynthesisOptions(scene, settings);
  BandsSimulation simulated;
  if (settings.bands == BandResolution::kThirdOctave) {
    // One simulation per third of every octave: the same rays and image sources, each
    // with its third's coefficients, air and diffraction (AcousticScene::thirdOctaveBands).
    std::array<BandsSimulation, 3> thirds;
    for (int k = 0; k < 3; ++k) thirds[static_cast<std::size_t>(k)] = simulateBands(scene.thirdOctaveBands(k), source, listener, settings, 0);
    result.impulse_response = synthesizeThirdOctaveImpulseResponse(
        {&thirds[0].paths, &thirds[1].paths, &thirds[2].paths}, {&thirds[0].late, &thirds[1].late, &thirds[2].late},
        synthesis);
    simulated = octaveSummary(thirds);
    for (BandsSimulation& third : thirds) result.late_thirds.push_back(std::move(third.late));
  } else {
    simulated = simulateBands(scene, source, listener, settings, ledger_budget_bytes);
    result.impulse_response = synthesizeImpulseResponse(simulated.paths, &simulated.late, synthesis);
  }
  result.paths = std::move(simulated.paths);
  result.late = std::move(simulated.late);
  result.stats = simulated.stats;
  result.ledger = std::move(simulated.ledger);
  if (low) result.impulse_response = joinWaveLowBand(*low, result.impulse_response, result.low_band);
  return result;
}

std::optional<SimulationResult> replaySimulation(const SimulationResult& traced, const AcousticScene& scene,
                                                 const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                                                 const SimulationSettings& settings, std::string& why_not) {
  const PathLedger* ledger = traced.ledger.get();
  const auto refuse = [&](const std::string& why) {
    why_not = why;
    return std::nullopt;
  };
  if (!ledger) return refuse("the traced result kept no paths");
  if (settings.mode != SimulationMode::kAccurate) return refuse("only the accurate mode traces paths");
  if (settings.diffraction_scattering) return refuse("diffraction scattering depends on each path's legs");
  if (settings.low_band != LowBandMethod::kGeometric) return refuse("the wave low band is solved, not traced");
  if (settings.bands != BandResolution::kOctave) return refuse("third octaves are traced once per third");
  if (ledger->source != source || ledger->listener != listener) return refuse("the positions differ from the traced ones");
  if (ledger->seed != settings.rays.seed || ledger->ray_count != settings.rays.ray_count ||
      ledger->image_source_order != settings.image_source_order ||
      ledger->bins != static_cast<std::size_t>(std::ceil(settings.duration_s / settings.rays.bin_s)) ||
      ledger->bin_s != settings.rays.bin_s) {
    return refuse("the ray tracing's settings differ from the traced ones");
  }
  const PropagationModel model = PropagationModel::from(settings.air, settings.directivity);
  LedgerReplayOptions options;
  options.threads = settings.rays.threads;
  LedgerReplay replay = replayLedger(*ledger, scene, model, options);
  if (!replay.replayed) return refuse(replay.why_not);
  SimulationResult result;
  result.speed_of_sound_m_s = model.speed_of_sound_m_s;
  result.eyring_t60_s = eyringReverberationTimes(scene, settings.air);
  result.paths = computeImageSources(scene, source, listener, model, imageSourceOptionsFor(settings));
  result.late = std::move(replay.histogram);
  result.stats = traced.stats;
  result.ledger = traced.ledger;
  result.impulse_response =
      synthesizeImpulseResponse(result.paths, &result.late, simulationSynthesisOptions(scene, settings));
  return result;
}

AudioBuffer synthesizeLatePart(const SimulationResult& result, const SynthesisOptions& synthesis) {
  if (result.late_thirds.size() == 3) {
    const std::vector<SpecularPath> none;
    return synthesizeThirdOctaveImpulseResponse({&none, &none, &none},
                                                {&result.late_thirds[0], &result.late_thirds[1], &result.late_thirds[2]},
                                                synthesis);
  }
  return synthesizeImpulseResponse({}, &result.late, synthesis);
}

ImageSourceOptions imageSourceOptionsFor(const SimulationSettings& settings) {
  ImageSourceOptions options;
  options.max_order = settings.image_source_order;
  options.diffraction_scattering = settings.diffraction_scattering;
  return options;
}

SynthesisOptions simulationSynthesisOptions(const AcousticScene& scene, const SimulationSettings& settings) {
  SynthesisOptions synthesis;
  synthesis.duration_s = settings.duration_s;
  synthesis.ambisonic_order = settings.ambisonic_order;
  synthesis.room_volume_m3 = scene.volumeM3() > 0.0 ? scene.volumeM3() : 100.0;
  synthesis.speed_of_sound_m_s = PropagationModel::from(settings.air, settings.directivity).speed_of_sound_m_s;
  synthesis.seed = settings.rays.seed;
  return synthesis;
}

}  // namespace room_reverb::core
