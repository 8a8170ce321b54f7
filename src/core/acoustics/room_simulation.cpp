#include "room_reverb/acoustics/room_simulation.h"

#include <cmath>
#include <limits>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

SimulationMode parseSimulationMode(const std::string& name) {
  if (name == "fast") return SimulationMode::kFast;
  if (name == "accurate") return SimulationMode::kAccurate;
  throw InputError("unknown simulation mode '" + name + "' (use fast or accurate)");
}

std::string toString(SimulationMode mode) { return mode == SimulationMode::kFast ? "fast" : "accurate"; }

OctaveBandValues eyringReverberationTimes(const AcousticScene& scene, const AirConditions& air) {
  const OctaveBandValues alpha = scene.meanAbsorption();
  const OctaveBandValues m = airEnergyAttenuationPerM(air);
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

EnergyHistogram parametricLateEnergy(const AcousticScene& scene, const PropagationModel& model,
                                     double direct_delay_s, int order, double duration_s, double bin_s) {
  const auto bins = static_cast<std::size_t>(std::ceil(duration_s / bin_s));
  EnergyHistogram histogram(bin_s, bins);
  const OctaveBandValues t60 = eyringReverberationTimes(scene, model.air);
  const double c = model.speed_of_sound_m_s;
  const double mean_free_time = 4.0 * scene.volumeM3() / (scene.surfaceM2() * c);
  // The image sources hold the first `order` reflections; the tail takes over after them
  // with a raised-cosine fade one mean free time wide.
  const double fade_start = direct_delay_s + std::max(0, order) * mean_free_time;
  const double fade_end = fade_start + mean_free_time;
  for (std::size_t bin = 0; bin < bins; ++bin) {
    const double t = (bin + 0.5) * bin_s;
    double weight = 1.0;
    if (t <= fade_start) continue;
    if (t < fade_end) weight = 0.5 - 0.5 * std::cos(kPi * (t - fade_start) / mean_free_time);
    for (int b = 0; b < kOctaveBandCount; ++b) {
      if (!std::isfinite(t60[b])) continue;
      const double delta = 6.0 * std::log(10.0) / t60[b];
      // A diffuse field of energy density exp(-delta t) / V carries c w per unit area and time.
      const double energy = weight * c / scene.volumeM3() * std::exp(-delta * t) * bin_s;
      histogram.add(t, b, energy, Eigen::Vector3d::Zero());
    }
  }
  return histogram;
}

SimulationResult simulateRoom(const AcousticScene& scene, const Eigen::Vector3d& source,
                              const Eigen::Vector3d& listener, const SimulationSettings& settings) {
  if (settings.image_source_order < 0) throw InputError("the image-source order must be 0 or more");
  if (!(settings.duration_s > 0.0 && settings.duration_s <= 30.0)) throw InputError("the response duration must be in (0, 30] s");
  scene.requireInside(source, "source");
  scene.requireInside(listener, "listener");
  if ((source - listener).norm() < 0.05) throw InputError("source and listener are closer than 5 cm");

  const PropagationModel model = PropagationModel::from(settings.air, settings.directivity);
  SimulationResult result;
  result.speed_of_sound_m_s = model.speed_of_sound_m_s;
  result.eyring_t60_s = eyringReverberationTimes(scene, settings.air);
  ImageSourceOptions image_options;
  image_options.max_order = settings.image_source_order;
  result.paths = computeImageSources(scene, source, listener, model, image_options);

  if (settings.mode == SimulationMode::kAccurate) {
    RayTracingOptions rays = settings.rays;
    rays.max_time_s = settings.duration_s;
    rays.image_source_order = settings.image_source_order;
    RayTracingResult traced = traceRays(scene, source, listener, model, rays);
    result.late = std::move(traced.histogram);
    result.stats = traced.stats;
  } else {
    const double direct_delay = (source - listener).norm() / model.speed_of_sound_m_s;
    result.late = parametricLateEnergy(scene, model, direct_delay, settings.image_source_order,
                                       settings.duration_s, settings.rays.bin_s);
  }

  SynthesisOptions synthesis;
  synthesis.duration_s = settings.duration_s;
  synthesis.ambisonic_order = settings.ambisonic_order;
  synthesis.room_volume_m3 = scene.volumeM3() > 0.0 ? scene.volumeM3() : 100.0;
  synthesis.speed_of_sound_m_s = model.speed_of_sound_m_s;
  synthesis.seed = settings.rays.seed;
  result.impulse_response = synthesizeImpulseResponse(result.paths, &result.late, synthesis);
  return result;
}

}  // namespace room_reverb::core
