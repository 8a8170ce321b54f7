#pragma once
// A shoebox room for the simulation tests: [0, size] with inward normals, one material.
#include <Eigen/Core>
#include <string>

#include "room_reverb/acoustics/air_absorption.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/ray_tracer.h"
#include "room_reverb/acoustics/triangle_mesh.h"

namespace room_reverb::test {

core::TriangleMesh shoeboxMesh(const Eigen::Vector3d& size, const std::string& material = "test_wall");

// A library holding one material with the same absorption and scattering in every band.
core::MaterialLibrary uniformLibrary(double absorption, double scattering, const std::string& name = "test_wall");

// Ray-tracing options of `rays` rays over `max_time_s`, on two threads.
inline core::RayTracingOptions twoThreads(std::size_t rays, double max_time_s) {
  core::RayTracingOptions options;
  options.ray_count = rays;
  options.max_time_s = max_time_s;
  options.threads = 2;
  return options;
}

// Air that absorbs nothing.
inline core::AirConditions noAir() {
  core::AirConditions air;
  air.enabled = false;
  return air;
}

}  // namespace room_reverb::test
