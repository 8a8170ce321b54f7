#pragma once
// Training the surface-material classifier (vision/material_classifier.h) on the capture
// generator's own textures: random rooms (random size, materials drawn family by family,
// furniture, rig pose, resolution, sensor noise, shading, faded textures) rendered from
// the rig's top camera, cut into rectified surface patches with their true room model
// exactly as vision/surface_materials.h cuts a fitted one, each patch labelled with the
// texture family of the material it shows.
//
// Every room comes from its own seed (derived from the options' seed and its index), so a
// training set and a test set made with different seeds share no room, and none is a
// scene of data/captures. `room_reverb train-materials` (scripts/train-material-classifier)
// runs trainMaterialClassifier and writes config/material_classifier.yml.gz.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/synthetic_capture/photo_textures.h"
#include "room_reverb/vision/material_classifier.h"

namespace room_reverb::core {

struct MaterialTrainingOptions {
  // Patches wanted per family; rooms are rendered until every family has them (or
  // max_rooms is reached).
  int patches_per_family = 800;
  int max_rooms = 1000;
  // At most this many patches of one surface (face or object) of one room, picked at
  // random, so the set spreads over many rooms, lights and resolutions.
  int max_patches_per_surface = 6;
  std::uint64_t seed = 1;
  // Equirect widths of the rendered rooms, each room one of these at random (repeat a
  // width to make it more likely).
  std::vector<int> widths = {512, 1024, 1024, 2048};
  MaterialPatchGeometry geometry;
  MaterialForestParams forest;
  int threads = 0;  // 0: all cores
  // Photographs of real surfaces (photo_textures.h): in every room a material of a family
  // they hold is painted with one of them with probability photo_share, else drawn.
  // None: drawn textures only.
  std::shared_ptr<const PhotoTextureSet> photo_textures;
  double photo_share = 0.5;
  // Collections of photo_textures kept out of training altogether: trainMaterialClassifier
  // evaluates on them (cross-source accuracy). Empty: no such evaluation.
  std::vector<std::string> held_out_sources;
  // Only patches of these families are sampled (empty: every family the library has).
  std::vector<TextureFamily> families;
};

struct MaterialSamples {
  cv::Mat features;                     // N x kMaterialFeatureLength, CV_32F
  std::vector<TextureFamily> families;  // the truth of each row
  std::vector<std::string> materials;   // the library material each row shows
  int rooms = 0;                        // rooms rendered
};

// InputError for options out of range (patches_per_family, max_rooms or
// max_patches_per_surface < 1, no widths or one the generator rejects, a patch geometry
// smaller than 0.05 m or 8 pixels).
MaterialSamples generateMaterialSamples(const MaterialTrainingOptions& options, const MaterialLibrary& library);

struct MaterialAccuracy {
  std::array<int, kTextureFamilyCount> correct{};  // allTextureFamilies() order
  std::array<int, kTextureFamilyCount> total{};
  // confusion[truth][predicted], allTextureFamilies() order.
  std::array<std::array<int, kTextureFamilyCount>, kTextureFamilyCount> confusion{};
  double overall() const;                  // fraction of all samples right
  double of(TextureFamily family) const;   // fraction right of one family's samples (0 if none)
};

MaterialAccuracy evaluateMaterialClassifier(const MaterialClassifier& classifier, const MaterialSamples& samples);

struct MaterialTrainingResult {
  MaterialClassifier classifier;
  int training_samples = 0;
  int training_rooms = 0;
  // On a separate set from other seeds, a quarter the size of the training set.
  MaterialAccuracy held_out;
  // Per collection of options.held_out_sources: on rooms painted only with its
  // photographs (the families it holds), a quarter the size of the training set.
  std::map<std::string, MaterialAccuracy> held_out_sources;
  double seconds = 0.0;
};

MaterialTrainingResult trainMaterialClassifier(const MaterialTrainingOptions& options, const MaterialLibrary& library);

// The seed of the held-out set that trainMaterialClassifier evaluates on.
std::uint64_t heldOutSeed(std::uint64_t training_seed);

}  // namespace room_reverb::core
