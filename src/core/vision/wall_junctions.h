#pragma once
// Where a wall meets the floor and the ceiling, as the colour image shows it.
//
// A far wall is a few pixels of disparity (7 m at 1024 px with a 0.2 m baseline: under
// 4 px, so a tenth of a pixel is 2.5 % of its range), and depth from another matcher may
// carry a bias that grows with range. The line where the wall meets the ceiling does not
// depend on the depth: with the camera's height below the ceiling h known from the near
// ceiling, a junction seen at elevation e lies at h / tan(e) along the wall's normal, and
// a pixel's error there moves it by h / sin^2(e) times the pixel's angle (0.21 m at 7.3 m,
// h = 1.6 m and 1024 px: coarser than the disparity, but without its bias and without
// needing texture on the wall).
//
// For each candidate position of a wall, that line is projected into the image and the
// colour step across it measured: per sample, the smallest of the differences (colour
// below - colour above) 1, 2 and 3 pixels out, along the mean step's direction; per line,
// the step that line_share of its samples reach. A junction separates two surfaces, so the
// step keeps its sign along the whole line and at every offset; texture and noise do not,
// a thin line parallel to the wall (a ceiling tile's joint) differs at one offset only,
// and a picture's or a window's edge, or wall units reaching the ceiling, across part of
// the wall are not what most of the line shows. The wall is where the step peaks. The
// floor's junction is not used: skirting boards and the furniture standing on the floor
// make a stronger step above it (on rendered rooms its peak lies 9-15 cm beyond walls
// 1.5-2.5 m away: a skirting 10 cm high).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "room_box_fit.h"

namespace room_reverb::core::layout {

struct JunctionParams {
  double step_px = 3.0;             // the colour is compared 1, 2 .. this many pixels either side of the line
  // Candidate positions: from the wall's fitted distance times 1 - search_inward to times
  // 1 + search_outward. Outwards further: a line there must also be in the rig's sight
  // (raysMeetJunction); inwards the rig's rays must stop at it, which depth that thins out
  // towards a far wall may not say.
  double search_inward = 0.35;
  double search_outward = 0.5;
  double position_step_m = 0.01;    // between candidate positions
  int samples_per_line = 96;        // along the wall's width
  double corner_margin = 0.1;       // share of the wall's width left out at each corner
  double max_off_normal_rad = 1.0;  // line samples seen further than this from the wall's normal are left out
  double min_contrast = 4.0;        // the step at the peak over its median over the candidates
  double line_share = 0.7;          // a line's step is the one this share of its samples reach
};

struct JunctionFit {
  bool found = false;        // the step peaks inside the search with at least min_contrast
  double position_m = 0.0;   // the wall's signed coordinate along its axis (aligned frame)
  double contrast = 0.0;     // the step at the peak over its median over the candidates
  double pixel_m = 0.0;      // one pixel at the junction, in metres along the wall's normal
};

// The top camera's equirect (8-bit, 3 channels) as ceilingJunction reads it: float and
// lightly blurred (sigma 0.7 px) so that a step is not one pixel's noise. Prepared once per
// image, as each wall's search reads the same one. Empty for an empty or non-colour image.
cv::Mat junctionImage(const cv::Mat& color);

// Where wall `face` (2..5, kRoomSurfaceNames order) of `box` (aligned frame: the rig at
// the origin) meets the ceiling in `image` (junctionImage of the top camera's equirect),
// where camera_from_aligned maps the aligned frame to the camera's (x forward, z up).
// Searched from search_inward inside the box's wall to search_outward beyond it. Needs a
// ceiling (box.has_ceiling); returns found = false otherwise.
JunctionFit ceilingJunction(const cv::Mat& image, const Eigen::Isometry3d& camera_from_aligned, const AlignedBox& box,
                            int face, const JunctionParams& params);

// Whether the rig's rays towards the wall just under a junction found at `position_m`
// (signed, as JunctionFit::position_m) meet the wall there: of the points of `raw`
// (aligned frame) on rays that pass the wall's plane within `band_m` under the ceiling and
// within the junction's samples across it, fewer than `max_off_share` end more than
// `tolerance_m` on the wrong side of the plane. A line further out than the depth's wall
// (`outwards`) is only the wall's junction if the rig can see it: rays that stop short of
// it are wrong (the top edge of wall units along a far wall, which depth ranges in front
// of that line: rendered held-out room 211 at 1024 px, the units' top across 59 % of the
// wall, 1.6 m beyond it). A line nearer than the depth's wall is only the wall's junction
// if the rays under it stop there: rays that go on beyond it are wrong (the near edge of a
// light hanging under the ceiling in front of a narrow far wall of the same colour as the
// ceiling: rendered held-out room 372 at 2048 px, 0.47 m in front of a wall 4.36 m away
// that the depth ranged within 7 cm). Too few such points (fewer than `min_points`) say
// nothing against it.
bool raysMeetJunction(const std::vector<WeightedPoint>& raw, const AlignedBox& box, int face, double position_m,
                      bool outwards, double camera_z, double band_m, double tolerance_m, const JunctionParams& params,
                      double max_off_share = 0.5, int min_points = 20);

}  // namespace room_reverb::core::layout
