#pragma once
// What every simulating command (simulate, compare) shares: the options that set up the
// simulation, their help text, and building the scene from a room model or a mesh file.
#include <set>
#include <string>

#include "arguments.h"
#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/room_simulation.h"

namespace room_reverb::tool {

extern const char* const kSimulationOptionsHelp;
std::set<std::string> simulationValueOptions();
std::set<std::string> simulationFlags();

// Mode, orders, rays, seed, threads, duration, receiver radius from the options.
core::SimulationSettings simulationSettingsFrom(const Arguments& args);

struct SceneFiles {
  std::string room_file;  // room.yaml, or ""
  std::string mesh_file;  // mesh, or ""
  core::UpAxis mesh_up_axis = core::UpAxis::kZ;
  bool open = false;
};

// The scene of a room model or mesh with the library (--materials) and overrides
// (--scattering) of the options; `air` gets the room model's air conditions (if a room
// model is given), then the options' --temperature, --humidity, --no-air on top.
core::AcousticScene sceneFrom(const SceneFiles& files, const Arguments& args, core::AirConditions& air);

}  // namespace room_reverb::tool
