#pragma once
// Depth from a vertically aligned pair of 360-degree cameras (the paper's section 3: two
// Ricoh Thetas one above the other; Kim & Hilton, "3D scene reconstruction from multiple
// spherical stereo pairs", IJCV 2013).
//
// With the baseline on the polar axis, a point's two images lie on the same column
// (azimuth) of the two equirectangular images: the epipolar lines are the columns. The
// images are transposed so that the columns become rows and matched by OpenCV's
// semi-global block matching (Hirschmüller 2008), whose disparity d is then an elevation
// difference of gamma = d * pi / H radians.
//
// Geometry (top camera T at +b/2, bottom camera B at -b/2 on the rig's z axis; polar
// angles theta from +z): a point P at polar angle theta_t from T and theta_b from B forms
// the triangle T B P with angle pi - theta_t at T, theta_b at B, and gamma = theta_t -
// theta_b at P. By the sine rule |TP| = b sin(theta_b) / sin(gamma): the range from the
// top camera, at the top image's pixel. The bottom camera sees P higher (theta_b <
// theta_t), so the disparity is positive.
//
// Around the matcher:
//   - exposure: the bottom image's grey levels carried onto the top's where the cameras
//     were exposed differently (match_exposure);
//   - the seam: each transposed image is padded with the columns of the other side of
//     +-180 degrees, so the matcher's paths run across it;
//   - the poles: a row of the transposed image is a half great circle from the zenith to
//     the nadir; it is continued beyond both poles by the half circle of the opposite
//     azimuth (the same great circle), so the matcher sees real texture there instead of
//     a border it cannot match;
//   - the polar caps, where the baseline points along the view and gamma vanishes, are
//     masked (polar_cap_deg);
//   - optional edge-preserving hole filling along the azimuth: a hole up to max_hole_px
//     between neighbours on one surface (ranges within hole_surface_ratio) is interpolated;
//     one next to a depth edge is an occlusion and takes the farther neighbour, not past a
//     colour edge (hole_color_tolerance).
#include <opencv2/core.hpp>

namespace room_reverb::core {

struct SphericalStereoOptions {
  double min_range_m = 0.3;      // nearest range searched: sets the disparity range (240 px at 2048 x 1024, b = 0.2 m)
  double max_range_m = 30.0;     // farther results are invalid
  double polar_cap_deg = 15.0;   // |elevation| above 90 - cap is masked
  int seam_padding_px = 32;      // columns copied across the +-180 degree seam
  // Semi-global matching (cv::StereoSGBM), in transposed-image pixels.
  int block_size = 5;            // odd, >= 1
  int p1_per_channel = 8;        // P1 = p1 * channels * block^2 (small disparity changes)
  int p2_per_channel = 32;       // P2 = p2 * channels * block^2 (jumps), > p1
  int uniqueness_ratio = 5;      // [%]
  int speckle_window_size = 100; // [px], 0: no speckle filter
  int speckle_range = 2;         // [disparity px]
  int disp12_max_diff = 1;       // left-right check [px], < 0: off
  int pre_filter_cap = 31;
  bool full_dp = false;          // 8 paths (MODE_HH) instead of 5; slower, a little better
  // Gauss-Newton refinement of each disparity on a (2 n + 1)^2 window of grey levels,
  // which removes the matcher's pull towards whole pixels (vision/subpixel_disparity.h).
  // On walls seen face-on at 2048 x 1024 (test_stereo_range_accuracy) the median range
  // error falls from 0.90 % to 0.54 % at 3-5 m and from 1.79 % to 1.50 % at 5-8 m. Without
  // it the pull is a bias: rendered cluttered rooms at 1024 x 512 come out about 2 % short
  // across one axis, 1 of 20 held-out rooms within 1 % in every dimension against 16 of
  // 20 with it (docs/visual-route.md).
  bool subpixel_refinement = true;
  int refinement_half_window_px = 3;  // n
  // After it, tiles of planar_tile_px^2 pixels that one plane explains (walls, floors,
  // table tops) take the plane fitted to all of the tile's grey levels
  // (src/core/vision/planar_disparity.h): a plain wall too smooth for the small window is
  // still ranged without the pull towards whole pixels. Walls face-on 5-8 m away
  // (test_stereo_range_accuracy): median error 0.55 % against 1.39 % without; 3-5 m 0.10
  // against 0.54 %. Needs subpixel_refinement.
  bool planar_refinement = true;
  int planar_tile_px = 32;            // 8..256
  double planar_max_range_m = 8.0;    // farther tiles keep the per-pixel disparities
  int threads = 0;                    // rows of the refinement and conversion (0: all cores)
  // Pixels whose texture the images' noise drowns get no range (vision/texture_snr.h):
  // where the energy of the grey-level gradient along the epipolar line, over a
  // (2 n + 1)^2 window, exceeds what the noise alone gives it by less than this ratio, and
  // no tile's plane (planar_refinement) ranged the pixel from its larger area. The noise is
  // measured on the pair itself. 0: every match is kept.
  double min_texture_snr = 0.25;
  int texture_half_window_px = 7;     // n
  // Where the pixels the matcher pairs in the pair at half size show the two cameras
  // exposed differently, carry the bottom image's grey levels onto the top's (per channel,
  // a gain and an offset: vision/photometric_match.h) before the full-size match, so that
  // two cameras exposed and white-balanced on their own neither lose matches nor bias the
  // disparities. The half-size match adds about a fifth of the full match's time.
  bool match_exposure = true;
  // Hole filling.
  bool fill_holes = true;
  int max_hole_px = 24;
  double hole_surface_ratio = 0.1;     // neighbours within 10 % of each other: one surface
  double hole_color_tolerance = 40.0;  // grey levels (max over channels)
};

struct SphericalDepth {
  cv::Mat range_m;     // CV_32FC1, top image's geometry: range from the top camera [m], NaN where invalid
  cv::Mat valid;       // CV_8UC1, 255 where range_m is a measurement (or a filled hole)
  cv::Mat filled;      // CV_8UC1, 255 where the value came from hole filling
  cv::Mat disparity_rad;  // CV_32FC1, gamma [rad], NaN where the matcher gave none
  int disparity_search_px = 0;  // the matcher's disparity range
};

// InputError for: empty images, images of different sizes or types, an image that is not
// 2:1 (width = 2 x height) or smaller than 64 x 32, black (max < 8) or saturated (min > 247)
// images, a baseline that is not positive and finite, options out of range.
SphericalDepth computeSphericalDepth(const cv::Mat& top, const cv::Mat& bottom, double baseline_m,
                                     const SphericalStereoOptions& options = {});

// The range [m] from the top camera of a point at the top image's polar angle theta_t [rad]
// whose disparity is gamma [rad]: b sin(theta_t - gamma) / sin(gamma). NaN for gamma <= 0.
double rangeFromDisparity(double theta_top_rad, double gamma_rad, double baseline_m);

}  // namespace room_reverb::core
