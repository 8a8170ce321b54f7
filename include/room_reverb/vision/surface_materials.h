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
  int threads = 0;  // 0: all cores
};

// What was decided for one face or object.
struct SurfaceMaterialDecision {
  std::string name;        // kRoomSurfaceNames entry, or "objects[k] (label)"
  bool seen = false;       // false: the unseen default (or the material it had) was kept
  TextureFamily family = TextureFamily::kPlaster;
  std::string material;
  double confidence = 0.0;  // area-weighted mean vote share of the family, in [0, 1]
  double seen_area_m2 = 0.0;
  int patches = 0;
};

// `top_color_equirect`: the top camera's CV_8UC3 equirect (width 2 x height), the image
// the layout was fitted from; the top camera sits at +baseline_m / 2 on the rig's z axis
// (layout.room_from_rig; rig frame = camera frame). Writes the material and confidence of
// every surface in layout.model.surfaces and every object (see above), and returns the
// decisions (each with the material's own confidence)
// (faces in kRoomSurfaceNames order without a missing ceiling, then objects).
// InputError for an empty or non-CV_8UC3 image, one not twice as wide as high, a
// non-positive or non-finite baseline, an untrained classifier, or a top camera outside
// the fitted box.
std::vector<SurfaceMaterialDecision> assignSurfaceMaterials(RoomLayout& layout, const cv::Mat& top_color_equirect,
                                                            double baseline_m, const MaterialClassifier& classifier,
                                                            const MaterialFamilyTable& families,
                                                            const SurfaceMaterialOptions& options = {});

}  // namespace room_reverb::core
