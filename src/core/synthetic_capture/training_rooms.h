#pragma once
// Random rooms for training the material classifier: a box of random size (sometimes
// open to the sky) whose faces and furniture-like cuboids get random library materials,
// drawn family first so that every texture family is equally common, with the camera rig
// at a random place and heading, and random capture settings (sensor noise, shading,
// faded textures). Each seed gives one room; training and test sets come from
// disjoint seeds, and none of them is one of the scenes in data/captures.
#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/synthetic_capture/capture_generator.h"

namespace room_reverb::core::material_detail {

struct TrainingRoom {
  RoomModel room;          // rig_position_m and rig_rotation are the rig's pose
  CaptureOptions options;  // seed, noise, shading, low-texture materials (the width is the caller's)
};

// The library's materials (aliases left out) grouped by texture family, in
// allTextureFamilies() order.
std::vector<std::vector<std::string>> libraryMaterialsByFamily(const MaterialLibrary& library);

TrainingRoom randomTrainingRoom(std::uint64_t seed, const std::vector<std::vector<std::string>>& materials_by_family);

}  // namespace room_reverb::core::material_detail
