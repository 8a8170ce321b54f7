#pragma once
// The material step of the visual route: fills the empty materials of a fitted room
// layout (vision/room_layout.h) from what the top camera saw of each face and object.
//
// For every plane of the fitted model (box faces; objects' sides and tops) the step lays
// square patches of the classifier's size on the plane, fills each from the top camera's
// equirect image where a ray from the camera reaches that plane first (so furniture in
// front of a wall is not taken for the wall), and classifies the patch's colour and
// texture (vision/material_classifier.h). A face's family is the area-weighted soft vote
// of its patches (each patch covers a known area of the surface, the part the mask
// keeps); the family becomes a library material through the family table
// (vision/material_families.h).
//
// Confidences: a face's is its family's area-weighted mean vote share. An object's
// confidence already says how sure the layout is of the box (furniture_fit), so it is
// multiplied by its material's. A face or object not seen enough that already has a
// material keeps it untouched; one without gets the table's unseen family (plaster:
// the commonest indoor finish) with a low confidence.
//
// A seen face whose vote is too close to call falls back by the table's fallback rules
// (material_families.h). Each decision also names the runner-up: the best family other
// than the chosen material's, so a user sees what else the surface could have been.
// Last, a materials override file (material_overrides.h) replaces what the user knows
// better; it is applied after the classifier, so each decision keeps what was found.
#include <array>
#include <string>
#include <vector>

#include "room_reverb/vision/material_classifier.h"
#include "room_reverb/vision/material_families.h"
#include "room_reverb/vision/room_layout.h"

namespace room_reverb::core {

struct SurfaceMaterialOptions {
  // A face or object whose classified patches cover less than this area [m^2] is "not
  // seen": it keeps its material if it has one, else it gets the table's unseen family
  // with unseen_confidence.
  double min_seen_area_m2 = 0.02;
  double unseen_confidence = 0.1;
  // Patches: the fraction of the patch the surface must fill, and the image pixels it
  // must span (fewer: too blurred to show texture).
  double min_patch_coverage = 0.25;
  double min_source_pixels = 6.0;
  // At most this many patches per face or object side, the nearest the camera (0: all;
  // vision/surface_patches.h): the step's time stays bounded on large faces.
  int max_patches_per_face = 100;
  int threads = 0;  // 0: all cores
  // A floor or ceiling whose joints repeat along both its axes is tiles, whatever its
  // patches' vote (vision/tile_joints.h). Not walls: a brick bond repeats so too.
  bool tile_joints = true;
  // A materials override file (format: material_overrides.h); "" for none. Read on each
  // call, so that a user can correct the file and build again.
  std::string override_file;
};

// The area-weighted vote of one face or object.
struct MaterialVote {
  std::array<double, kTextureFamilyCount> votes{};  // area [m^2] x vote share, per family (allTextureFamilies() order)
  double area_m2 = 0.0;                             // area of the classified patches
  int patches = 0;
};

// What was decided for one face or object.
struct SurfaceMaterialDecision {
  std::string name;        // kRoomSurfaceNames entry, or "objects[k] (label)"
  bool seen = false;       // false: the unseen default (or the material it had) was kept
  TextureFamily family = TextureFamily::kPlaster;
  std::string material;
  double confidence = 0.0;  // area-weighted mean vote share of the family, in [0, 1]; 1 when overridden
  // The best family other than the chosen material's, its material at this placement and
  // its vote share; runner_up is empty when nothing else had a vote (or it was not seen).
  TextureFamily runner_up_family = TextureFamily::kPlaster;
  std::string runner_up;
  double runner_up_confidence = 0.0;
  // The vote was below the table's min_confidence and the placement's fallback rule chose.
  bool fell_back = false;
  std::string fallback_reason;
  // A floor or ceiling whose joints repeat along both its axes is tiles whatever its patches
  // looked like (a patch shows one or two joints of large tiles; vision/tile_joints.h):
  // the family is tiles, its confidence the weaker axis's strength, the vote's winner the
  // runner-up, and this says what was seen.
  bool joint_grid = false;
  std::string joint_grid_reason;
  // The override file named this face or object: material and confidence are the user's;
  // found_material and found_confidence what the route had found.
  bool overridden = false;
  std::string found_material;
  double found_confidence = 0.0;
  double seen_area_m2 = 0.0;
  int patches = 0;
};

// The decision for a face or object at `placement` from its vote (area_m2 > 0): the winning
// family, or the fallback rule's choice when the winner's share is below the table's
// min_confidence, with the runner-up. InputError for a vote without area.
SurfaceMaterialDecision decideFromVote(const MaterialVote& vote, SurfacePlacement placement,
                                       const MaterialFamilyTable& families);

// `top_color_equirect`: the top camera's CV_8UC3 equirect (width 2 x height), the image
// the layout was fitted from; the top camera sits at +baseline_m / 2 on the rig's z axis
// (layout.room_from_rig; rig frame = camera frame). Writes the material and confidence of
// every surface in layout.model.surfaces and every object (see above), and returns the
// decisions (each with the material's own confidence)
// (faces in kRoomSurfaceNames order without a missing ceiling, then objects).
// The room model's surfaces and objects also get the runner-up (SurfaceAssignment and
// CuboidObject runner_up, runner_up_confidence; cleared where overridden).
// InputError for an empty or non-CV_8UC3 image, one not twice as wide as high, a
// non-positive or non-finite baseline, an untrained classifier, a top camera outside
// the fitted box, or an override file that cannot be read or does not fit the model
// (loadMaterialOverrides, resolveMaterialOverrides).
std::vector<SurfaceMaterialDecision> assignSurfaceMaterials(RoomLayout& layout, const cv::Mat& top_color_equirect,
                                                            double baseline_m, const MaterialClassifier& classifier,
                                                            const MaterialFamilyTable& families,
                                                            const SurfaceMaterialOptions& options = {});

}  // namespace room_reverb::core
