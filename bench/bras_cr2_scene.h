#pragma once
// The BRAS CR2 room (scene 9) as the simulation benchmarks use it: the repository's
// directory, the scene as `room_reverb simulate --mesh cr2_scene9.ac --y-up` builds it,
// and the pair LS01 - receiver 1.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/triangle_mesh.h"

namespace room_reverb::bench {

inline std::string sourceDir() {
#ifdef ROOM_REVERB_SOURCE_DIR
  return ROOM_REVERB_SOURCE_DIR;
#else
  // The build does not say where the repository is: this file lies in its bench/.
  const std::string file = __FILE__;
  const auto slash = file.find_last_of('/');
  return slash == std::string::npos ? std::string("..") : file.substr(0, slash) + "/..";
#endif
}

// Source LS01 and receiver 1 in the room frame (z up).
inline const Eigen::Vector3d kCr2Source(0.931, -2.547, 0.723);
inline const Eigen::Vector3d kCr2Receiver(-0.993, 1.426, 1.230);

// Built once; null (and the benchmark skipped with the reason) when the mesh or the
// materials fail to load.
inline const core::AcousticScene* cr2Scene(benchmark::State& state) {
  static std::string error;
  static const std::unique_ptr<core::AcousticScene> scene = []() -> std::unique_ptr<core::AcousticScene> {
    try {
      core::TriangleMesh mesh = core::loadMesh(sourceDir() + "/data/bras_cr2/geometry/cr2_scene9.ac", core::UpAxis::kY);
      return std::make_unique<core::AcousticScene>(std::move(mesh), core::MaterialLibrary::loadDefault());
    } catch (const std::exception& e) {
      error = e.what();
      return nullptr;
    }
  }();
  if (!scene) state.SkipWithError(("CR2 scene: " + error).c_str());
  return scene.get();
}

}  // namespace room_reverb::bench
