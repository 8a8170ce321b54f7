#pragma once
// Tiles laid in a grid, told by their joints across a whole face. The classifier sees one
// 0.6 m patch at a time, and a patch of floor tiles 0.3 m or larger shows one or two
// joints: it reads as the stone, wood or plaster of the tiles' faces (a collection of
// tile photographs the classifier never saw is 20 % right patch by patch,
// docs/visual-route.md). Over a whole floor or ceiling the joints repeat: the face's
// patches laid side by side (they tile the face) show lines of gradient at a fixed
// period along both of the face's axes, which planks (one axis: their butt joints are
// staggered), carpet, concrete and plaster do not. Parquet laid in herringbone repeats
// along both axes as well, and so does a brick bond (its head joints, staggered from
// course to course, fall every half brick): the material step asks floors and ceilings
// only.
#include <vector>

#include "room_reverb/vision/surface_patches.h"

namespace room_reverb::core::material_detail {

struct JointGrid {
  // Along each of the face's axes (s: the patches' columns, t: their rows): the period
  // [m] of the joint profile (the mean gradient across the axis, per position along it),
  // the shortest lag between kMinJointPeriodM and kMaxJointPeriodM whose autocorrelation
  // peak is within 80 % of the highest (a period repeats at its multiples), and its
  // normalised autocorrelation there. 0 where the face shows too little of that axis.
  double strength_s = 0.0, strength_t = 0.0;
  double period_s_m = 0.0, period_t_m = 0.0;
  // Both axes repeat at least at kGridStrength: tiles laid in a grid.
  bool grid = false;
};

// Tiles' periods: mosaic and ceiling tiles from 0.1 m to large floor tiles of 1.0 m.
constexpr double kMinJointPeriodM = 0.1;
constexpr double kMaxJointPeriodM = 1.0;
// Measured on the development rooms painted with the ufoai collection's photographs (24
// rooms at 1024 px, the weaker axis): 19 of 23 tiled faces 0.69-0.95 (four 0.00-0.48),
// the 114 faces of plaster, carpet and wood at most 0.36 but for one patterned carpet at
// 0.57 (which the patches take for tiles as well).
constexpr double kGridStrength = 0.6;

// The joint grid of one face from its patches (all of one target, cut by
// sampleSurfacePatches with patch size `patch_size_m`).
JointGrid jointGridOfFace(const std::vector<const SurfacePatch*>& patches, double patch_size_m);

}  // namespace room_reverb::core::material_detail
