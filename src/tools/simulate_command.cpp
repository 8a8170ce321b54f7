// room_reverb simulate: the impulse response of a room model or mesh for a source and a
// listener, by image sources plus ray tracing (accurate) or a parametric tail (fast).
#include <iomanip>
#include <iostream>

#include "arguments.h"
#include "command.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/common/error.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb simulate (--room ROOM.yaml | --mesh FILE [--y-up] [--open])
                            --source X Y Z --listener X Y Z --out IR.wav
                            [--mode fast|accurate] [--order N] [--rays N] [--seed N]
                            [--ambisonic-order N] [--duration S] [--threads N]
                            [--materials FILE] [--no-air] [--temperature C] [--humidity PCT]
                            [--scattering S] [--receiver-radius M]

Simulates the room impulse response from a source to a listener (metres, room frame) and
writes it as AmbiX (ACN/SN3D) at 48 kHz, 32-bit float; --ambisonic-order 0 writes omni.

  --room FILE          room model in the room.yaml format (inline materials allowed)
  --mesh FILE          AC3D (.ac), OBJ or PLY mesh whose material names are in the library
  --y-up               the mesh file has y up (as the BRAS models); turned to z up
  --open               the mesh is open (rays leaving it are not leaks)
  --mode MODE          accurate (image sources + ray tracing, default) or fast
                       (image sources + Eyring tail)
  --order N            image-source order (default 3)
  --rays N             rays (default 100000)
  --seed N             random seed (default 1); same seed and threads, same output
  --threads N          worker threads (default: all cores)
  --ambisonic-order N  0 to 3 (default 1)
  --duration S         response length in seconds (default 2)
  --materials FILE     material library (default config/materials.yaml)
  --no-air             no air absorption (default: ISO 9613-1 at the room's air conditions,
                       20 C and 50 % unless the room file or the options say otherwise)
  --temperature C, --humidity PCT   air conditions
  --scattering S       one scattering coefficient for every surface (default: materials')
  --receiver-radius M  detection sphere for specular rays (default 0.3)
Prints a summary (paths, rays, leaks, Eyring T60 per band). Exit 2 for bad input.
)";

// Takes "--name X Y Z" out of `args` and returns the three numbers.
Eigen::Vector3d takeVector(std::vector<std::string>& args, const std::string& name) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] != "--" + name) continue;
    if (i + 3 >= args.size()) throw UsageError("--" + name + " needs three numbers X Y Z");
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) {
      const std::string& text = args[i + 1 + static_cast<std::size_t>(k)];
      char* end = nullptr;
      v[k] = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0') throw UsageError("--" + name + " needs three numbers, got '" + text + "'");
    }
    args.erase(args.begin() + static_cast<long>(i), args.begin() + static_cast<long>(i) + 4);
    return v;
  }
  throw UsageError("--" + name + " X Y Z is required");
}

int runSimulate(const std::vector<std::string>& raw) {
  std::vector<std::string> rest = raw;
  const Eigen::Vector3d source = takeVector(rest, "source");
  const Eigen::Vector3d listener = takeVector(rest, "listener");
  const Arguments args(rest,
                       {"room", "mesh", "out", "mode", "order", "rays", "seed", "threads", "ambisonic-order",
                        "duration", "materials", "temperature", "humidity", "scattering", "receiver-radius"},
                       {"y-up", "open", "no-air"});
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (args.has("room") == args.has("mesh")) throw UsageError("give exactly one of --room and --mesh");
  if (!args.has("out")) throw UsageError("--out IR.wav is required");

  const MaterialLibrary base = args.has("materials") ? MaterialLibrary::load(args.value("materials", ""))
                                                     : MaterialLibrary::loadDefault();
  SimulationSettings settings;
  settings.mode = parseSimulationMode(args.value("mode", "accurate"));
  settings.image_source_order = args.intValue("order", 3);
  const int rays = args.intValue("rays", 100000);
  if (rays <= 0) throw InputError("--rays must be at least 1");
  settings.rays.ray_count = static_cast<std::size_t>(rays);
  settings.rays.seed = static_cast<std::uint32_t>(args.intValue("seed", 1));
  settings.rays.threads = args.intValue("threads", 0);
  settings.rays.receiver_radius_m = args.doubleValue("receiver-radius", 0.3);
  settings.ambisonic_order = args.intValue("ambisonic-order", 1);
  settings.duration_s = args.doubleValue("duration", 2.0);

  TriangleMesh mesh;
  MaterialLibrary library = base;
  bool closed = !args.has("open");
  if (args.has("room")) {
    const RoomModel room = loadRoomModel(args.value("room", ""));
    mesh = roomModelToMesh(room);
    library = materialsFor(room, base);
    settings.air = room.air;
    closed = room.has_ceiling;
  } else {
    mesh = loadMesh(args.value("mesh", ""), args.has("y-up") ? UpAxis::kY : UpAxis::kZ);
  }
  settings.air.temperature_c = args.doubleValue("temperature", settings.air.temperature_c);
  settings.air.humidity_percent = args.doubleValue("humidity", settings.air.humidity_percent);
  if (args.has("no-air")) settings.air.enabled = false;
  MaterialOverrides overrides;
  if (args.has("scattering")) overrides.global_scattering = args.doubleValue("scattering", 0.0);

  const AcousticScene scene(std::move(mesh), library, overrides, closed);
  const SimulationResult result = simulateRoom(scene, source, listener, settings);
  writeAudioFile(args.value("out", ""), result.impulse_response, SampleEncoding::kFloat32);

  std::cout << std::fixed << std::setprecision(3);
  std::cout << "room: " << scene.mesh().triangleCount() << " triangles, " << scene.planes().size() << " planes, V "
            << scene.volumeM3() << " m^3, S " << scene.surfaceM2() << " m^2\n";
  std::cout << "mode " << toString(settings.mode) << ": " << result.paths.size() << " image-source paths";
  if (settings.mode == SimulationMode::kAccurate) {
    std::cout << ", " << result.stats.rays << " rays, " << result.stats.reflections << " reflections, "
              << result.stats.leaked_rays << " leaked, " << result.stats.escaped_rays << " escaped";
  }
  std::cout << "\nEyring T60 with air (s):";
  for (double t : result.eyring_t60_s) std::cout << " " << t;
  std::cout << "\nwrote " << args.value("out", "") << " (" << result.impulse_response.channelCount() << " channels, "
            << result.impulse_response.durationS() << " s)\n";
  return 0;
}

const CommandRegistration registration({"simulate", "impulse response of a room model or mesh (image sources + rays)", kHelp, runSimulate});

}  // namespace
}  // namespace room_reverb::tool
