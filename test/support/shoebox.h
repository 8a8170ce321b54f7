#pragma once
// A shoebox room for the simulation tests: [0, size] with inward normals, one material.
#include <Eigen/Core>
#include <string>

#include "room_reverb/acoustics/air_absorption.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/triangle_mesh.h"

namespace room_reverb::test {

core::TriangleMesh shoeboxMesh(const Eigen::Vector3d& size, const std::string& material = "test_wall");

// A library holding one material with the same absorption and scattering in every band.
core::MaterialLibrary uniformLibrary(double absorption, double scattering, const std::string& name = "test_wall");

// Air that absorbs nothing.
inline core::AirConditions noAir() {
  core::AirConditions air;
  air.enabled = false;
  return air;
}

}  // namespace room_reverb::test
