#include "room_reverb/vision/surface_materials.h"

#include <array>
#include <cmath>

#include "room_reverb/common/error.h"
#include "room_reverb/vision/surface_patches.h"

namespace room_reverb::core {
namespace {

using namespace material_detail;

struct Tally {
  std::array<double, kTextureFamilyCount> votes{};  // area x vote share, per family
  double area_m2 = 0.0;
  int patches = 0;
};

void checkInputs(const RoomLayout& layout, const cv::Mat& image, double baseline_m, const MaterialClassifier& classifier) {
  if (image.empty()) throw InputError("surface materials: the top camera's image is empty");
  if (image.type() != CV_8UC3) {
    throw InputError("surface materials: the top camera's image must be 8-bit BGR (CV_8UC3), got type " + std::to_string(image.type()));
  }
  if (image.cols != 2 * image.rows) {
    throw InputError("surface materials: the image is " + std::to_string(image.cols) + " x " + std::to_string(image.rows) +
                     "; an equirect image is twice as wide as high");
  }
  if (!(baseline_m > 0.0) || !std::isfinite(baseline_m)) {
    throw InputError("surface materials: the baseline must be a positive, finite distance in metres");
  }
  if (!classifier.trained()) throw InputError("surface materials: the material classifier is not trained (load one first)");
  if (!(layout.model.size_m.array() > 0.0).all()) throw InputError("surface materials: the layout's room box has no size");
}

SurfacePlacement placementOf(int target) {
  if (target == 0) return SurfacePlacement::kFloor;
  if (target == 1) return SurfacePlacement::kCeiling;
  return target < 6 ? SurfacePlacement::kWall : SurfacePlacement::kObject;
}

// The family with the largest area-weighted vote, or the unseen default (keeping a
// material the model already had: someone put it there for a reason).
SurfaceMaterialDecision decide(const Tally& tally, int target, const std::string& current_material, double current_confidence,
                               const MaterialFamilyTable& families, const SurfaceMaterialOptions& options) {
  SurfaceMaterialDecision decision;
  decision.seen_area_m2 = tally.area_m2;
  decision.patches = tally.patches;
  decision.seen = tally.area_m2 >= options.min_seen_area_m2 && tally.patches > 0;
  if (!decision.seen) {
    if (!current_material.empty()) {
      decision.family = textureFamilyFor(current_material).family;
      decision.material = current_material;
      decision.confidence = current_confidence;
    } else {
      decision.family = families.unseen_family;
      decision.material = families.materialFor(decision.family, placementOf(target));
      decision.confidence = options.unseen_confidence;
    }
    return decision;
  }
  int best = 0;
  for (int k = 1; k < kTextureFamilyCount; ++k) {
    if (tally.votes[static_cast<std::size_t>(k)] > tally.votes[static_cast<std::size_t>(best)]) best = k;
  }
  decision.family = textureFamilyAt(best);
  decision.material = families.materialFor(decision.family, placementOf(target));
  decision.confidence = tally.votes[static_cast<std::size_t>(best)] / tally.area_m2;
  return decision;
}

}  // namespace

std::vector<SurfaceMaterialDecision> assignSurfaceMaterials(RoomLayout& layout, const cv::Mat& top_color_equirect,
                                                            double baseline_m, const MaterialClassifier& classifier,
                                                            const MaterialFamilyTable& families,
                                                            const SurfaceMaterialOptions& options) {
  checkInputs(layout, top_color_equirect, baseline_m, classifier);
  RoomModel& model = layout.model;
  const Eigen::Isometry3d room_from_camera = layout.room_from_rig * Eigen::Translation3d(0.0, 0.0, 0.5 * baseline_m);
  const Eigen::Vector3d camera = room_from_camera.translation();
  if (!camera.allFinite() || !(camera.array() > 0.0).all() || !(camera.array() < model.size_m.array()).all()) {
    throw InputError("surface materials: the top camera is outside the fitted room box; check the layout's room_from_rig");
  }

  PatchSampling sampling;
  sampling.geometry = classifier.patchGeometry();
  sampling.min_coverage = options.min_patch_coverage;
  sampling.min_source_pixels = options.min_source_pixels;
  sampling.threads = options.threads;
  const std::vector<SurfacePatch> patches = sampleSurfacePatches(top_color_equirect, model, room_from_camera, sampling);

  std::vector<Tally> tallies(6 + model.objects.size());
  if (!patches.empty()) {
    std::vector<const SurfacePatch*> all;
    for (const SurfacePatch& patch : patches) all.push_back(&patch);
    const std::vector<MaterialPrediction> predictions = classifier.predictAll(patchFeatures(all, options.threads));
    for (std::size_t i = 0; i < patches.size(); ++i) {
      Tally& tally = tallies[static_cast<std::size_t>(patches[i].target)];
      for (int k = 0; k < kTextureFamilyCount; ++k) {
        tally.votes[static_cast<std::size_t>(k)] += patches[i].area_m2 * predictions[i].posterior[static_cast<std::size_t>(k)];
      }
      tally.area_m2 += patches[i].area_m2;
      ++tally.patches;
    }
  }

  std::vector<SurfaceMaterialDecision> decisions;
  for (int f = 0; f < 6; ++f) {
    if (f == 1 && !model.has_ceiling) continue;
    SurfaceAssignment& surface = model.surfaces[kRoomSurfaceNames[static_cast<std::size_t>(f)]];
    if (layout.face_evidence[static_cast<std::size_t>(f)].open) {
      // An open side has no surface to classify: what the camera sees there is beyond it.
      SurfaceMaterialDecision open;
      open.name = kRoomSurfaceNames[static_cast<std::size_t>(f)];
      open.material = surface.material;
      open.confidence = surface.confidence;
      open.family = TextureFamily::kOpening;
      decisions.push_back(open);
      continue;
    }
    SurfaceMaterialDecision decision =
        decide(tallies[static_cast<std::size_t>(f)], f, surface.material, surface.confidence, families, options);
    decision.name = kRoomSurfaceNames[static_cast<std::size_t>(f)];
    surface.material = decision.material;
    surface.confidence = decision.confidence;
    decisions.push_back(decision);
  }
  for (std::size_t k = 0; k < model.objects.size(); ++k) {
    CuboidObject& object = model.objects[k];
    const int target = 6 + static_cast<int>(k);
    SurfaceMaterialDecision decision =
        decide(tallies[static_cast<std::size_t>(target)], target, object.material, object.confidence, families, options);
    decision.name = "objects[" + std::to_string(k) + "] (" + object.label + ")";
    // An object's one confidence also says how sure the layout is of the box itself, so
    // the material's multiplies it. A material it already had is left as it was.
    const bool kept = !decision.seen && !object.material.empty();
    if (!kept) {
      object.material = decision.material;
      object.confidence *= decision.confidence;
    }
    decisions.push_back(decision);
  }
  return decisions;
}

}  // namespace room_reverb::core
