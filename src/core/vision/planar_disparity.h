#pragma once
// Disparities of plain planar surfaces, one plane per tile. On a wall too plain for a
// small window (smooth plaster at 5-8 m) the window's grey levels carry too little
// gradient for the per-pixel step of subpixel_disparity.h, and the matcher's pull towards
// whole pixels stays: a tenth of a pixel, over 1 % of the range at 8 m. A tile of 32 x 32
// pixels holds twenty times the window's samples. Where one plane explains the tile's
// disparities, the plane is moved to the least-squares minimum of the squared grey
// difference over all of the tile's pixels on it (the photometric step of
// subpixel_disparity.h with the plane's three parameters in place of one disparity).
// The tiles are laid twice, the second grid offset by half a tile, and a pixel takes the
// planes' disparity where the two tiles holding it agree on it: a tile across a crease (a
// wall meeting the ceiling) takes the other surface's pixels near the crease onto its
// plane, and the offset tile does not.
//
// The plane is linear in inverse range: a point on the plane n.X = D seen along the unit
// ray x has 1/r = (n / D).x, so rho = m.x with m = n / D, for any plane not through the
// camera. The disparity of inverse range rho at the top camera's polar angle theta
// follows from the triangle of spherical_stereo.h: the bottom camera sees the point at
// theta_b = atan2(sin theta, cos theta + b rho), and gamma = theta - theta_b.
#include <opencv2/core.hpp>

#include "subpixel_disparity.h"

namespace room_reverb::core::stereo_detail {

struct PlanarRefinementGrid {
  double baseline_m = 0.2;
  int seam_padding_px = 0;  // rows of the transposed images before azimuth column 0
  int pole_padding_px = 0;  // columns of the transposed images before polar row 0
  int tile_px = 32;
  double max_range_m = 8.0;  // tiles farther than this keep the per-pixel disparities
  int threads = 0;
};

// disparity_px: CV_32FC1 on the top image's grid (rows: polar angle from the zenith,
// columns: azimuth), NaN where there is none; changed in place where the two grids' planes
// agree. left and right are the transposed images the disparities were matched on.
// Returns the number of pixels that took a plane's disparity; `taken`, when given, becomes
// a CV_8UC1 mask of them (255).
long refineDisparityByPlanes(const EpipolarImage& left, const EpipolarImage& right, cv::Mat& disparity_px,
                             const PlanarRefinementGrid& grid, cv::Mat* taken = nullptr);

// d gamma / d rho: how fast the disparity gamma [rad] at the top camera's polar angle
// theta [rad] changes with inverse range rho [1/m].
double disparitySlopeInInverseRange(double theta_rad, double rho_per_m, double baseline_m);

}  // namespace room_reverb::core::stereo_detail
