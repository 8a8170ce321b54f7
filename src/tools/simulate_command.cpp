// room_reverb simulate: the impulse response of a room model or mesh for a source and a
// listener, by image sources plus ray tracing (accurate) or a parametric tail (fast).
#include <iomanip>
#include <iostream>

#include "arguments.h"
#include "command.h"
#include "simulation_arguments.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/common/error.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelpHead = R"(usage: room_reverb simulate (--room ROOM.yaml | --mesh FILE [--y-up] [--open])
                            --source X Y Z --listener X Y Z --out IR.wav
                            [--mode accurate|fast|eyring] [--order N] [--rays N] [--seed N]
                            [--ambisonic-order N] [--duration S] [--threads N]
                            [--materials FILE] [--no-air] [--temperature C] [--humidity PCT]
                            [--scattering S] [--receiver-radius M]
                            [--diffraction-scattering] [--low-band geometric|wave [--crossover HZ]]
                            [--bands octave|third]

Simulates the room impulse response from a source to a listener (metres, room frame) and
writes it as AmbiX (ACN/SN3D) at 48 kHz, 32-bit float; --ambisonic-order 0 writes omni.

  --room FILE          room model in the room.yaml format (inline materials allowed)
  --mesh FILE          AC3D (.ac), OBJ or PLY mesh whose material names are in the library
  --y-up               the mesh file has y up (as the BRAS models); turned to z up
  --open               the mesh is open (rays leaving it are not leaks)
)";
const char* kHelpTail = "Prints a summary (paths, rays, leaks, Eyring T60 per band). Exit 2 for bad input.\n";

int runSimulate(const std::vector<std::string>& raw) {
  std::vector<std::string> rest = raw;
  const Eigen::Vector3d source = takeRequiredVector(rest, "source");
  const Eigen::Vector3d listener = takeRequiredVector(rest, "listener");
  std::set<std::string> valued = simulationValueOptions();
  valued.insert({"room", "mesh", "out"});
  std::set<std::string> flags = simulationFlags();
  flags.insert({"y-up", "open"});
  const Arguments args(rest, valued, flags);
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (args.has("room") == args.has("mesh")) throw UsageError("give exactly one of --room and --mesh");
  if (!args.has("out")) throw UsageError("--out IR.wav is required");

  SimulationSettings settings = simulationSettingsFrom(args);
  const SceneFiles files{args.value("room", ""), args.value("mesh", ""), args.has("y-up") ? UpAxis::kY : UpAxis::kZ,
                         args.has("open")};
  const AcousticScene scene = sceneFrom(files, args, settings.air);
  const SimulationResult result =
      simulateRoom(scene, source, listener, settings, [](const std::string& line) { std::cerr << line << "\n"; });
  writeAudioFile(args.value("out", ""), result.impulse_response, SampleEncoding::kFloat32);

  std::cout << std::fixed << std::setprecision(3);
  std::cout << "room: " << scene.mesh().triangleCount() << " triangles, " << scene.planes().size() << " planes, V "
            << scene.volumeM3() << " m^3, S " << scene.surfaceM2() << " m^2\n";
  std::cout << "mode " << toString(settings.mode);
  if (settings.bands == BandResolution::kThirdOctave) {
    std::cout << " in third octaves (" << (scene.hasThirdOctaveMaterials() ? "the materials' thirds" : "no material has thirds")
              << "; one simulation per third, counts summed)";
  }
  std::cout << ": " << result.paths.size() << " image-source paths";
  if (settings.mode != SimulationMode::kEyring) {
    std::cout << ", " << result.stats.rays << " rays, " << result.stats.reflections << " reflections, "
              << result.stats.leaked_rays << " leaked, " << result.stats.escaped_rays << " escaped, receiver sphere "
              << result.stats.receiver_radius_m << " m\nbands traced until (s), then continued analytically:";
    for (double t : result.stats.traced_until_s) std::cout << " " << t;
  }
  if (result.low_band.used) {
    const WaveLowBandStats& low = result.low_band;
    std::cout << "\nwave low band below " << std::setprecision(0) << low.crossover_hz << " Hz: " << low.solver_runs
              << " solver runs on " << low.grid_cells << " cells of " << std::setprecision(3) << low.grid_spacing_m
              << " m, " << std::setprecision(1) << low.seconds << " s; level against the geometric response at the crossover "
              << std::showpos << low.overlap_level_db << std::noshowpos << " dB" << std::setprecision(3);
  }
  std::cout << "\nEyring T60 with air (s):";
  for (double t : result.eyring_t60_s) std::cout << " " << t;
  std::cout << "\nwrote " << args.value("out", "") << " (" << result.impulse_response.channelCount() << " channels, "
            << result.impulse_response.durationS() << " s)\n";
  return 0;
}

const CommandRegistration registration({"simulate", "impulse response of a room model or mesh (image sources + rays)",
                                         std::string(kHelpHead) + kSimulationOptionsHelp + kHelpTail, runSimulate});

}  // namespace
}  // namespace room_reverb::tool
