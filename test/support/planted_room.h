#pragma once
// Random rooms with one planted model defect, for the diagnosis tests: a furnished-free
// shoebox with its own materials (scattering 0.5, so that ray-traced decay times are stable
// from seed to seed), four source-receiver pairs, and a "measurement" simulated from the
// room with the planted extension (B-format, more rays and other seeds than the diagnosis
// uses). The diagnosis is then given the room without the extension.
#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/diagnosis/diagnosis.h"

namespace room_reverb::test {

struct PlantedCase {
  std::uint32_t seed = 0;
  std::string cause;  // "" for no planted effect
  core::RoomModel room;                 // what the diagnosis is given
  core::ModelExtension planted;         // what the measurement has on top
  core::MaterialLibrary library;
  core::MeasuredEvidence evidence;
  std::string description;              // for the test log
};

// The seed is taken from ROOM_REVERB_TEST_SEED when set (to rerun a failure), else
// `default_seed`; it is printed either way.
std::uint32_t testSeed(std::uint32_t default_seed);

PlantedCase plantedCase(const std::string& cause, std::uint32_t seed);

// Diagnosis options sized for tests (few rays, short responses).
core::DiagnosisOptions testDiagnosisOptions();

}  // namespace room_reverb::test
