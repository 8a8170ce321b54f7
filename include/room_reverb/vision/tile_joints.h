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
  // How far the joints stand out as lines: the profile folded at its period (the mean of
  // each phase over the periods), its highest phase over its median phase. 0 without a
  // period.
  double line_contrast_s = 0.0, line_contrast_t = 0.0;
  // Both axes repeat at least at kGridStrength and their joints stand out at least at
  // kLineContrast: tiles laid in a grid.
  bool grid = false;
};

// Tiles' periods: mosaic and ceiling tiles from 0.1 m to large floor tiles of 1.0 m.
constexpr double kMinJointPeriodM = 0.1;
constexpr double kMaxJointPeriodM = 1.0;
// A grid of tiles is joint lines along both axes: each axis repeats, and each axis's
// joints stand out from the faces between them. Planks repeat along their width only;
// where a photograph of planks repeats along their length too (a rendered floor, a
// pattern printed on vinyl) its butt joints are no lines. Measured on the floors whose
// photographs the classifier does not take for tiles in the development rooms (40 with
// the sweethome3d collection, 24 with ufoai) and the looked-at held-out rooms 203-222,
// 341-360 and 381-400, at 1024 px (the weaker axis): the 14 floors of wood and carpet
// that repeat at 0.3 or more stand out at 1.19-1.49; the 18 tiled floors repetition alone
// missed at 1.27-2.64 (15 of them at 1.82 or more), the 19 it found at 1.42-3.30; a carpet
// whose pattern stands out at 2.75 repeats at 0.22.
// Repetition alone (0.6 on both axes, with no line test) took 5 wooden floors for tiles
// and missed 14 tiled ones there.
constexpr double kGridStrength = 0.3;
constexpr double kLineContrast = 1.5;

// The joint grid of one face from its patches (all of one target, cut by
// sampleSurfacePatches with patch size `patch_size_m`).
JointGrid jointGridOfFace(const std::vector<const SurfacePatch*>& patches, double patch_size_m);

}  // namespace room_reverb::core::material_detail
