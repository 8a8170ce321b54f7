#include "simulation_arguments.h"

#include <optional>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/common/error.h"

namespace room_reverb::tool {

using namespace room_reverb::core;

const char* const kSimulationOptionsHelp = R"(  --mode MODE          accurate (image sources + ray tracing, default), fast (image
                       sources + the late part of 2000-64000 rays: a preview) or eyring (image sources + Eyring tail: the
                       paper's fast route)
  --order N            image-source order (default 3)
  --rays N             rays (default 100000; fast mode: at most 64000, see --fast-tolerance)
  --fast-tolerance X   the fast mode's pilot of 2000 rays (four batches) is its decay when
                       every octave from 125 Hz to 4 kHz knows its decay rate within this
                       relative standard error there (default 0.02), else one run of
                       --rays rays, or of fewer where they would cost more than 3.2
                       million reflections at the pilot's rate; 0: always --rays rays
  --fast-track-radius M  that run's receiver: the track the rays run within M metres of
                       the listener (default 2; docs/simulation.md)
  --fast-launch-mixture X  that run's share of rays launched where the pilot's late
                       energy was launched (default 0.5; 0: uniform; docs/simulation.md)
  --seed N             random seed (default 1); same seed and threads, same output
  --threads N          worker threads (default: all cores)
  --ambisonic-order N  0 to 3 (default 1)
  --duration S         response length in seconds (default 2)
  --materials FILE     material library (default config/materials.yaml)
  --no-air             no air absorption (default: ISO 9613-1 at the room's air conditions,
                       20 C and 50 % unless the input files or the options say otherwise)
  --temperature C, --humidity PCT   air conditions
  --scattering S       one scattering coefficient for every surface (default: materials')
  --receiver-radius M  detection sphere for specular rays (default 0: from the volume
                       and ray count, see docs/simulation.md)
  --diffraction-scattering
                       add to each reflection's scattering what the surface's finite
                       size diffracts (Rindel's strip model; default: the materials'
                       scattering alone; docs/simulation.md)
  --low-band METHOD    geometric (default) or wave: below the crossover the first-order
                       channels from a wave (FDTD) solver on the room's grid
                       (docs/simulation.md)
  --crossover HZ       where the wave low band hands over (default 500)
  --bands RES          octave (default) or third: simulate and synthesise in third octaves
                       with the materials' third-octave coefficients where they have them
                       (three times the time; docs/simulation.md)
  --trace-to-end       trace every band to the end of the response (default: a band whose
                       decay is established, 25 dB down and straight, is continued
                       analytically; docs/simulation.md)
)";

std::set<std::string> simulationValueOptions() {
  return {"mode", "order", "rays", "seed", "threads", "ambisonic-order", "duration", "materials", "temperature",
          "humidity", "scattering", "receiver-radius", "fast-tolerance", "fast-track-radius", "fast-launch-mixture", "low-band", "crossover", "bands"};
}

std::set<std::string> simulationFlags() { return {"no-air", "trace-to-end", "diffraction-scattering"}; }

SimulationSettings simulationSettingsFrom(const Arguments& args) {
  SimulationSettings settings;
  settings.mode = parseSimulationMode(args.value("mode", "accurate"));
  settings.image_source_order = args.intValue("order", 3);
  const int rays = args.intValue("rays", static_cast<int>(settings.mode == SimulationMode::kFast ? settings.fast_ray_count
                                                                                                  : settings.rays.ray_count));
  if (rays <= 0) throw InputError("--rays must be at least 1");
  (settings.mode == SimulationMode::kFast ? settings.fast_ray_count : settings.rays.ray_count) = static_cast<std::size_t>(rays);
  settings.fast_rays.rate_tolerance = args.doubleValue("fast-tolerance", settings.fast_rays.rate_tolerance);
  if (!(settings.fast_rays.rate_tolerance >= 0.0 && settings.fast_rays.rate_tolerance < 1.0)) {
    throw InputError("--fast-tolerance must be 0 (a fixed ray count) or a share below 1");
  }
  settings.fast_rays.track_radius_m = args.doubleValue("fast-track-radius", settings.fast_rays.track_radius_m);
  if (!(settings.fast_rays.track_radius_m > 0.0 && settings.fast_rays.track_radius_m <= 100.0)) {
    throw InputError("--fast-track-radius must be a positive number of metres (at most 100)");
  }
  settings.fast_rays.late_launch_mixture = args.doubleValue("fast-launch-mixture", settings.fast_rays.late_launch_mixture);
  if (!(settings.fast_rays.late_launch_mixture >= 0.0 && settings.fast_rays.late_launch_mixture <= 0.9)) {
    throw InputError("--fast-launch-mixture must be a share from 0 to 0.9");
  }
  settings.rays.seed = static_cast<std::uint32_t>(args.intValue("seed", 1));
  settings.rays.threads = args.intValue("threads", 0);
  settings.rays.receiver_radius_m = args.doubleValue("receiver-radius", 0.0);
  settings.rays.continue_established_decays = !args.has("trace-to-end");
  settings.diffraction_scattering = args.has("diffraction-scattering");
  settings.low_band = parseLowBandMethod(args.value("low-band", "geometric"));
  settings.wave.crossover_hz = args.doubleValue("crossover", settings.wave.crossover_hz);
  if (args.has("crossover") && settings.low_band != LowBandMethod::kWave) {
    throw InputError("--crossover needs --low-band wave");
  }
  settings.bands = parseBandResolution(args.value("bands", "octave"));
  settings.ambisonic_order = args.intValue("ambisonic-order", 1);
  settings.duration_s = args.doubleValue("duration", 2.0);
  return settings;
}

AcousticScene sceneFrom(const SceneFiles& files, const Arguments& args, AirConditions& air) {
  const MaterialLibrary base = args.has("materials") ? MaterialLibrary::load(args.value("materials", ""))
                                                     : MaterialLibrary::loadDefault();
  MaterialOverrides overrides;
  if (args.has("scattering")) overrides.global_scattering = args.doubleValue("scattering", 0.0);
  std::optional<AcousticScene> scene;
  if (!files.room_file.empty()) {
    const RoomModel room = loadRoomModel(files.room_file);
    scene.emplace(roomModelToScene(room, base, overrides));
    air = room.air;
  } else {
    scene.emplace(loadMesh(files.mesh_file, files.mesh_up_axis), base, overrides, !files.open);
  }
  air.temperature_c = args.doubleValue("temperature", air.temperature_c);
  air.humidity_percent = args.doubleValue("humidity", air.humidity_percent);
  if (args.has("no-air")) air.enabled = false;
  return std::move(*scene);
}

}  // namespace room_reverb::tool
