#include "room_reverb/vision/surface_materials.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "room_reverb/common/error.h"
#include "room_reverb/vision/material_overrides.h"
#include "room_reverb/vision/surface_patches.h"
#include "room_reverb/vision/tile_joints.h"

namespace room_reverb::core {
namespace {

using namespace material_detail;

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

bool isSeen(const MaterialVote& vote, const SurfaceMaterialOptions& options) {
  return vote.area_m2 >= options.min_seen_area_m2 && vote.patches > 0;
}

SurfacePlacement placementOf(int target) {
  if (target == 0) return SurfacePlacement::kFloor;
  if (target == 1) return SurfacePlacement::kCeiling;
  return target < 6 ? SurfacePlacement::kWall : SurfacePlacement::kObject;
}

// The family's index in a vote (allTextureFamilies() order).
std::size_t at(TextureFamily family) { return static_cast<std::size_t>(textureFamilyIndex(family)); }

// A share of the vote as the printout gives it: two decimals.
std::string shareText(double share) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", share);
  return text;
}

// The fallback rule's choice for a vote whose winner `best` is below min_confidence.
void fallBack(SurfaceMaterialDecision& decision, const std::array<double, kTextureFamilyCount>& shares, std::size_t best,
              SurfacePlacement placement, const PlacementFallback& rule, const MaterialFamilyTable& families) {
  std::string reason = "the vote for " + toString(textureFamilyAt(static_cast<int>(best))) + " (" + shareText(shares[best]) +
                       ") is below min_confidence " + shareText(families.fallback.min_confidence) + "; ";
  bool by_look = false;
  std::size_t look = 0;
  for (const TextureFamily family : rule.by_look) {
    const std::size_t k = at(family);
    if (!by_look || shares[k] > shares[look]) look = k;
    by_look = true;
  }
  if (by_look && shares[look] >= rule.min_share) {
    decision.family = textureFamilyAt(static_cast<int>(look));
    decision.material = families.materialFor(decision.family, placement);
    reason += toString(decision.family) + " has " + shareText(shares[look]) + " of it (at least min_share " +
              shareText(rule.min_share) + "): the " + toString(placement) + " looks like " + toString(decision.family);
  } else {
    decision.material = rule.material;
    decision.family = textureFamilyFor(rule.material).family;
    reason += "the commonest " + toString(placement) + " material";
    if (by_look) reason += " (no family the " + toString(placement) + " is commonly made of has min_share " + shareText(rule.min_share) + ")";
  }
  decision.fell_back = true;
  decision.fallback_reason = reason;
}

// Tiles for a face whose joints repeat and stand out as lines along both its axes: the
// vote's choice becomes the runner-up.
void applyJointGrid(SurfaceMaterialDecision& decision, const JointGrid& grid, SurfacePlacement placement,
                    const MaterialFamilyTable& families) {
  char reason[224];
  std::snprintf(reason, sizeof reason,
                "joints repeat every %.2f x %.2f m (strength %.2f, %.2f; lines %.1f, %.1f times the faces between); "
                "the patches' vote was %s (%.2f)",
                grid.period_s_m, grid.period_t_m, grid.strength_s, grid.strength_t, grid.line_contrast_s,
                grid.line_contrast_t, toString(decision.family).c_str(), decision.confidence);
  decision.runner_up_family = decision.family;
  decision.runner_up = decision.material;
  decision.runner_up_confidence = decision.confidence;
  decision.family = TextureFamily::kTiles;
  decision.material = families.materialFor(TextureFamily::kTiles, placement);
  decision.confidence = std::min(1.0, std::min(grid.strength_s, grid.strength_t));
  decision.fell_back = false;
  decision.fallback_reason.clear();
  decision.joint_grid = true;
  decision.joint_grid_reason = reason;
}

// The unseen default, or the material the model already had (someone put it there for a
// reason), for a face or object the camera did not see enough of.
SurfaceMaterialDecision unseen(const MaterialVote& vote, SurfacePlacement placement, const std::string& current_material,
                               double current_confidence, const MaterialFamilyTable& families,
                               const SurfaceMaterialOptions& options) {
  SurfaceMaterialDecision decision;
  decision.seen_area_m2 = vote.area_m2;
  decision.patches = vote.patches;
  if (!current_material.empty()) {
    decision.family = textureFamilyFor(current_material).family;
    decision.material = current_material;
    decision.confidence = current_confidence;
  } else {
    decision.family = families.unseen_family;
    decision.material = families.materialFor(decision.family, placement);
    decision.confidence = options.unseen_confidence;
  }
  return decision;
}

// What the override file sets replaces the decision, which keeps what was found.
void applyOverride(SurfaceMaterialDecision& decision, const std::string& material) {
  decision.overridden = true;
  decision.found_material = decision.material;
  decision.found_confidence = decision.confidence;
  decision.material = material;
  decision.family = textureFamilyFor(material).family;
  decision.confidence = 1.0;
}

}  // namespace

SurfaceMaterialDecision decideFromVote(const MaterialVote& vote, SurfacePlacement placement,
                                       const MaterialFamilyTable& families) {
  if (!(vote.area_m2 > 0.0) || !std::isfinite(vote.area_m2)) {
    throw InputError("surface materials: a vote needs the positive area of the patches it was cast on");
  }
  SurfaceMaterialDecision decision;
  decision.seen = true;
  decision.seen_area_m2 = vote.area_m2;
  decision.patches = vote.patches;
  std::array<double, kTextureFamilyCount> shares{};
  std::size_t best = 0;
  for (std::size_t k = 0; k < shares.size(); ++k) {
    shares[k] = vote.votes[k] / vote.area_m2;
    if (shares[k] > shares[best]) best = k;
  }
  decision.family = textureFamilyAt(static_cast<int>(best));
  decision.material = families.materialFor(decision.family, placement);
  const auto rule = families.fallback.rules.find(placement);
  if (shares[best] < families.fallback.min_confidence && rule != families.fallback.rules.end()) {
    fallBack(decision, shares, best, placement, rule->second, families);
  }
  decision.confidence = shares[at(decision.family)];
  // The runner-up is the best family other than the one chosen, so a fallback's runner-up
  // is the close winner it set aside.
  bool any = false;
  std::size_t second = 0;
  for (std::size_t k = 0; k < shares.size(); ++k) {
    if (textureFamilyAt(static_cast<int>(k)) == decision.family || !(shares[k] > 0.0)) continue;
    if (!any || shares[k] > shares[second]) second = k;
    any = true;
  }
  if (any) {
    decision.runner_up_family = textureFamilyAt(static_cast<int>(second));
    decision.runner_up = families.materialFor(decision.runner_up_family, placement);
    decision.runner_up_confidence = shares[second];
  }
  return decision;
}

std::vector<SurfaceMaterialDecision> assignSurfaceMaterials(RoomLayout& layout, const cv::Mat& top_color_equirect,
                                                            double baseline_m, const MaterialClassifier& classifier,
                                                            const MaterialFamilyTable& families,
                                                            const SurfaceMaterialOptions& options) {
  checkInputs(layout, top_color_equirect, baseline_m, classifier);
  if (options.max_patches_per_face < 0) {
    throw InputError("surface materials: max_patches_per_face must be 0 (no limit) or positive");
  }
  RoomModel& model = layout.model;
  // The override file is read and checked against the model first: a mistake in it is
  // reported before the classifier's seconds are spent.
  std::vector<std::string> overrides(6 + model.objects.size());
  if (!options.override_file.empty()) {
    MaterialLibrary library = MaterialLibrary::loadDefault();
    for (const AcousticMaterial& material : model.inline_materials) library.add(material);
    overrides = resolveMaterialOverrides(loadMaterialOverrides(options.override_file, library), model);
  }
  const Eigen::Isometry3d room_from_camera = layout.room_from_rig * Eigen::Translation3d(0.0, 0.0, 0.5 * baseline_m);
  const Eigen::Vector3d camera = room_from_camera.translation();
  if (!camera.allFinite() || !(camera.array() > 0.0).all() || !(camera.array() < model.size_m.array()).all()) {
    throw InputError("surface materials: the top camera is outside the fitted room box; check the layout's room_from_rig");
  }

  PatchSampling sampling;
  sampling.geometry = classifier.patchGeometry();
  sampling.min_coverage = options.min_patch_coverage;
  sampling.min_source_pixels = options.min_source_pixels;
  sampling.max_patches_per_rect = options.max_patches_per_face;
  sampling.threads = options.threads;
  const std::vector<SurfacePatch> patches = sampleSurfacePatches(top_color_equirect, model, room_from_camera, sampling);

  std::vector<MaterialVote> tallies(6 + model.objects.size());
  if (!patches.empty()) {
    std::vector<const SurfacePatch*> all;
    for (const SurfacePatch& patch : patches) all.push_back(&patch);
    const std::vector<MaterialPrediction> predictions = classifier.predictAll(patchFeatures(all, options.threads));
    for (std::size_t i = 0; i < patches.size(); ++i) {
      MaterialVote& tally = tallies[static_cast<std::size_t>(patches[i].target)];
      for (int k = 0; k < kTextureFamilyCount; ++k) {
        tally.votes[static_cast<std::size_t>(k)] += patches[i].area_m2 * predictions[i].posterior[static_cast<std::size_t>(k)];
      }
      tally.area_m2 += patches[i].area_m2;
      ++tally.patches;
    }
  }

  // The floor's and the ceiling's patches, for their joints.
  std::array<std::vector<const SurfacePatch*>, 2> face_patches;
  for (const SurfacePatch& patch : patches) {
    if (patch.target < 2) face_patches[static_cast<std::size_t>(patch.target)].push_back(&patch);
  }
  std::vector<SurfaceMaterialDecision> decisions;
  for (int f = 0; f < 6; ++f) {
    if (f == 1 && !model.has_ceiling) continue;
    const std::size_t face = static_cast<std::size_t>(f);
    SurfaceAssignment& surface = model.surfaces[kRoomSurfaceNames[face]];
    SurfaceMaterialDecision decision;
    if (layout.face_evidence[face].open) {
      // An open side has no surface to classify: what the camera sees there is beyond it.
      decision.material = surface.material;
      decision.confidence = surface.confidence;
      decision.family = TextureFamily::kOpening;
    } else if (isSeen(tallies[face], options)) {
      decision = decideFromVote(tallies[face], placementOf(f), families);
      // Floors and ceilings only: a brick bond's joints repeat along both axes too (its
      // staggered head joints every half brick), and brick is a common wall.
      if (options.tile_joints && f < 2 && decision.family != TextureFamily::kTiles) {
        const JointGrid grid = jointGridOfFace(face_patches[face], sampling.geometry.size_m);
        if (grid.grid) applyJointGrid(decision, grid, placementOf(f), families);
      }
    } else {
      decision = unseen(tallies[face], placementOf(f), surface.material, surface.confidence, families, options);
    }
    decision.name = kRoomSurfaceNames[face];
    if (!overrides[face].empty()) applyOverride(decision, overrides[face]);
    surface.material = decision.material;
    surface.confidence = decision.confidence;
    surface.runner_up = decision.overridden ? "" : decision.runner_up;
    surface.runner_up_confidence = surface.runner_up.empty() ? 0.0 : decision.runner_up_confidence;
    decisions.push_back(decision);
  }
  for (std::size_t k = 0; k < model.objects.size(); ++k) {
    CuboidObject& object = model.objects[k];
    const std::size_t target = 6 + k;
    const MaterialVote& vote = tallies[target];
    SurfaceMaterialDecision decision = isSeen(vote, options)
                                           ? decideFromVote(vote, SurfacePlacement::kObject, families)
                                           : unseen(vote, SurfacePlacement::kObject, object.material, object.confidence, families, options);
    decision.name = "objects[" + std::to_string(k) + "] (" + object.label + ")";
    // An object's one confidence also says how sure the layout is of the box itself, so
    // the material's multiplies it. A material it already had is left as it was, unless
    // the user overrides it.
    const bool kept = !decision.seen && !object.material.empty();
    if (!overrides[target].empty()) applyOverride(decision, overrides[target]);
    if (!kept || decision.overridden) object.material = decision.material;
    if (!kept) object.confidence *= decision.confidence;
    object.runner_up = decision.overridden ? "" : decision.runner_up;
    object.runner_up_confidence = object.runner_up.empty() ? 0.0 : decision.runner_up_confidence;
    decisions.push_back(decision);
  }
  return decisions;
}

}  // namespace room_reverb::core
