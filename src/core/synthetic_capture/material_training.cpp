#include "room_reverb/synthetic_capture/material_training.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <random>

#include "room_reverb/common/error.h"
#include "room_reverb/vision/surface_patches.h"
#include "training_rooms.h"
#include "value_noise.h"

namespace room_reverb::core {
namespace {

using namespace material_detail;

void checkOptions(const MaterialTrainingOptions& options) {
  if (options.patches_per_family < 1 || options.max_rooms < 1 || options.max_patches_per_surface < 1) {
    throw InputError("material training: patches_per_family, max_rooms and max_patches_per_surface must be at least 1");
  }
  if (!(options.geometry.size_m >= 0.05) || options.geometry.pixels < 8) {
    throw InputError("material training: patches must be at least 0.05 m and 8 pixels across");
  }
  if (options.threads < 0) throw InputError("material training: threads must be 0 (all cores) or more");
  if (!(options.photo_share >= 0.0 && options.photo_share <= 1.0)) {
    throw InputError("material training: photo_share must be in [0, 1]");
  }
  if (options.widths.empty()) throw InputError("material training: no capture widths to render at");
  for (const int width : options.widths) {
    if (width < 64 || width % 2 != 0) throw InputError("material training: capture width " + std::to_string(width) + " must be even and >= 64");
  }
}

// The material each capture id shows: box faces by name, then objects.
std::string materialOf(const RoomModel& room, int target) {
  if (target < 6) return room.surfaces.at(kRoomSurfaceNames[static_cast<std::size_t>(target)]).material;
  return room.objects[static_cast<std::size_t>(target - 6)].material;
}

// Up to `limit` patches of each surface, chosen at random.
std::vector<const SurfacePatch*> pickPatches(const std::vector<SurfacePatch>& patches, int limit, std::mt19937_64& rng) {
  std::map<int, std::vector<const SurfacePatch*>> by_target;
  for (const SurfacePatch& patch : patches) by_target[patch.target].push_back(&patch);
  std::vector<const SurfacePatch*> picked;
  for (auto& [target, list] : by_target) {
    std::shuffle(list.begin(), list.end(), rng);
    const std::size_t keep = std::min(list.size(), static_cast<std::size_t>(limit));
    picked.insert(picked.end(), list.begin(), list.begin() + static_cast<std::ptrdiff_t>(keep));
  }
  return picked;
}

}  // namespace

std::uint64_t heldOutSeed(std::uint64_t training_seed) { return capture_detail::hashCombine(training_seed, 0x4e1d07ULL); }

MaterialSamples generateMaterialSamples(const MaterialTrainingOptions& options, const MaterialLibrary& library) {
  checkOptions(options);
  const auto by_family = libraryMaterialsByFamily(library);
  std::array<bool, kTextureFamilyCount> wanted{};
  for (std::size_t f = 0; f < wanted.size(); ++f) {
    const TextureFamily family = textureFamilyAt(static_cast<int>(f));
    wanted[f] = !by_family[f].empty() && (options.families.empty() || std::find(options.families.begin(), options.families.end(),
                                                                                 family) != options.families.end());
  }
  std::array<int, kTextureFamilyCount> count{};
  auto full = [&] {
    for (std::size_t f = 0; f < count.size(); ++f) {
      if (wanted[f] && count[f] < options.patches_per_family) return false;
    }
    return true;
  };
  PatchSampling sampling;
  sampling.geometry = options.geometry;
  sampling.threads = options.threads;
  MaterialSamples samples;
  for (int r = 0; r < options.max_rooms && !full(); ++r) {
    const std::uint64_t room_seed = capture_detail::hashCombine(options.seed, static_cast<std::uint64_t>(r));
    TrainingRoom t = randomTrainingRoom(room_seed, by_family);
    t.options.threads = options.threads;
    t.options.photo_textures = options.photo_textures;
    t.options.photo_share = options.photo_share;
    t.options.width = options.widths[capture_detail::hashCombine(room_seed, 0x3d7ULL) % options.widths.size()];
    const double half_baseline = 0.5 * t.options.baseline_m;
    const Eigen::Vector3d camera = t.room.rig_position_m + t.room.rig_rotation * Eigen::Vector3d(0, 0, half_baseline);
    const CameraCapture capture = renderCaptureCamera(t.room, library, t.options, camera, t.room.rig_rotation);
    Eigen::Isometry3d room_from_camera = Eigen::Isometry3d::Identity();
    room_from_camera.translation() = camera;
    room_from_camera.linear() = t.room.rig_rotation.toRotationMatrix();
    const std::vector<SurfacePatch> patches = sampleSurfacePatches(capture.color, t.room, room_from_camera, sampling);
    std::mt19937_64 rng(room_seed);
    std::vector<const SurfacePatch*> picked;
    for (const SurfacePatch* patch : pickPatches(patches, options.max_patches_per_surface, rng)) {
      const std::string material = materialOf(t.room, patch->target);
      const auto f = static_cast<std::size_t>(textureFamilyIndex(textureFamilyFor(material).family));
      int& n = count[f];
      if (!wanted[f] || n >= options.patches_per_family) continue;
      ++n;
      picked.push_back(patch);
      samples.materials.push_back(material);
      samples.families.push_back(textureFamilyFor(material).family);
    }
    samples.features.push_back(patchFeatures(picked, options.threads));
    samples.rooms = r + 1;
  }
  return samples;
}

double MaterialAccuracy::overall() const {
  int right = 0, all = 0;
  for (std::size_t k = 0; k < total.size(); ++k) {
    right += correct[k];
    all += total[k];
  }
  return all > 0 ? static_cast<double>(right) / all : 0.0;
}

double MaterialAccuracy::of(TextureFamily family) const {
  const auto k = static_cast<std::size_t>(textureFamilyIndex(family));
  return total[k] > 0 ? static_cast<double>(correct[k]) / total[k] : 0.0;
}

MaterialAccuracy evaluateMaterialClassifier(const MaterialClassifier& classifier, const MaterialSamples& samples) {
  MaterialAccuracy accuracy;
  if (samples.families.empty()) return accuracy;
  const std::vector<MaterialPrediction> predictions = classifier.predictAll(samples.features);
  for (std::size_t i = 0; i < predictions.size(); ++i) {
    const auto k = static_cast<std::size_t>(textureFamilyIndex(samples.families[i]));
    ++accuracy.total[k];
    if (predictions[i].family == samples.families[i]) ++accuracy.correct[k];
    ++accuracy.confusion[k][static_cast<std::size_t>(textureFamilyIndex(predictions[i].family))];
  }
  return accuracy;
}

MaterialTrainingResult trainMaterialClassifier(const MaterialTrainingOptions& options, const MaterialLibrary& library) {
  const auto start = std::chrono::steady_clock::now();
  MaterialTrainingOptions train = options;
  if (options.photo_textures && !options.held_out_sources.empty()) {
    train.photo_textures = std::make_shared<const PhotoTextureSet>(options.photo_textures->withoutSources(options.held_out_sources));
  } else if (!options.held_out_sources.empty()) {
    throw InputError("material training: held-out photo collections named but no photo textures given");
  }
  const MaterialSamples training = generateMaterialSamples(train, library);
  MaterialTrainingResult result;
  result.classifier = MaterialClassifier::train(training.features, training.families, options.geometry, options.forest);
  result.training_samples = training.features.rows;
  result.training_rooms = training.rooms;
  MaterialTrainingOptions held_out = train;
  held_out.seed = heldOutSeed(options.seed);
  held_out.patches_per_family = std::max(1, options.patches_per_family / 4);
  result.held_out = evaluateMaterialClassifier(result.classifier, generateMaterialSamples(held_out, library));
  for (const std::string& source : options.held_out_sources) {
    // Rooms painted only with the collection's photographs, sampled only where a
    // photograph is painted: the families it holds.
    MaterialTrainingOptions other = held_out;
    other.seed = heldOutSeed(held_out.seed);
    other.photo_textures = std::make_shared<const PhotoTextureSet>(options.photo_textures->onlySources({source}));
    other.photo_share = 1.0;
    other.families.clear();
    for (const TextureFamily family : allTextureFamilies()) {
      if (other.photo_textures->hasFamily(family)) other.families.push_back(family);
    }
    result.held_out_sources[source] = evaluateMaterialClassifier(result.classifier, generateMaterialSamples(other, library));
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace room_reverb::core
