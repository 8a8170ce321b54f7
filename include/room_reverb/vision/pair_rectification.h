#pragma once
// The two cameras of a rig as they stand on its bar. The spherical stereo searches each
// image column for its match, which holds only when both cameras face the same way.
// Two consumer cameras screwed to a bar never quite do: the bottom camera stands turned
// against the top one by a fraction of a degree to a degree or two.
//
// - A turn about the bar moves every match sideways off its column (0.3 degrees is
//   0.9 px at 1024 px wide) and the matcher loses it.
// - A tilt adds to each disparity an angle that goes with the sine of the azimuth: half
//   the room's far walls come nearer and the other half recede (1 mrad is 2.5 % of the
//   range of a wall 5 m away at a 0.2 m baseline).
//
// The turn is found from the pair itself. Corresponding points satisfy the epipolar
// constraint on the sphere, b_top . (t x R b_bottom) = 0, for the turn R (bottom camera
// -> top camera) and the baseline t along the top camera's pole: ORB features matched
// between the two images, each followed into the bottom image to a fraction of a pixel
// (Lucas-Kanade), a RANSAC on three matches, then Gauss-Newton on the inliers. Rectified,
// the bottom image is turned to face as the top one does, and the stereo sees the pair
// it assumes. The bar's own lean against the top camera's pole is not found: it shows
// only in the parallax of near points, and a fit of it on rendered rooms took the
// matches' errors for a lean of 1-18 mrad where there was none.
#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>

namespace room_reverb::core {

struct PairRectificationOptions {
  bool enabled = true;
  // Features are found on the images shrunk to this width [px] (0: as they are), and
  // followed to a fraction of a pixel on the images as they are: at 1024 px ORB places a
  // match within about 3 mrad, and hundreds of them, followed at full size, give the turn
  // to a few tenths of a mrad at half the time of finding them at full size.
  int feature_width = 1024;
  int max_features = 3000;  // ORB keypoints per image
  // Only features within this of the horizon: nearer the poles the equirectangular image
  // stretches them, and along the baseline there is no parallax to tell the pose by.
  double max_elevation_rad = 1.05;
  double ratio = 0.8;                 // Lowe's test: best match's distance under this share of the second's
  double max_parallax_rad = 0.35;     // a match's disparity at most this (a point 0.6 m away at 0.2 m)
  double max_turn_rad = 0.09;         // the turn sought within 5 degrees of none
  double inlier_tolerance_px = 2.0;   // a match agrees within this many pixels of the feature image
  int ransac_iterations = 400;
  int min_inliers = 40;               // fewer: the pair is left as it is (a warning says why)
  // Rectified only where the turn is at least min_angle_rad and min_significance standard
  // errors of its fit. A pair rendered standing true reads up to 0.45 mrad; a smaller
  // turn moves a match by a sixth of a pixel at 1024 px along the azimuth, which the
  // stereo bears, and the tilt it leaves in the disparities is the range bias's to find
  // (vision/range_bias.h).
  double min_angle_rad = 1e-3;
  double min_significance = 4.0;
  std::uint64_t seed = 1;  // the RANSAC's samples: the same seed, the same result
};

struct PairRectification {
  Eigen::Matrix3d bottom_to_top = Eigen::Matrix3d::Identity();  // bottom camera frame -> top camera frame
  double turn_rad = 0.0;                                          // the angle of bottom_to_top
  double turn_standard_error_rad = 0.0;                           // of turn_rad, from the fit's scatter
  int matches = 0;                  // feature pairs through the ratio test and the gates
  int inliers = 0;
  double residual_rad = 0.0;        // median |epipolar residual| of the inliers
  bool estimated = false;           // enough inliers to say
  bool applied = false;             // large and clear enough to rectify for
  // The bottom image's turn into the top camera's frame (R d: a direction d of its
  // frame there): bottom_to_top where applied, else identity.
  Eigen::Matrix3d bottom_rotation = Eigen::Matrix3d::Identity();
};

// The pose of the bottom camera against the top one, from two equirectangular images of
// the same size (8-bit, one or three channels). InputError for empty images, images of
// different sizes or types, images that are not 2:1 or not 8-bit, and options out of
// range. Images with too few features to match (a black or plain pair) are not an error:
// `estimated` is false.
PairRectification estimatePairRectification(const cv::Mat& top, const cv::Mat& bottom,
                                             const PairRectificationOptions& options = {});

// The epipolar residual [rad] of a match: the angle by which b_top misses the great
// circle through the baseline `t` (bottom -> top camera) and R b_bottom (the plane of the
// two rays). Zero for a pair of views of one point.
double epipolarResidual(const Eigen::Vector3d& b_top, const Eigen::Vector3d& b_bottom, const Eigen::Matrix3d& R,
                        const Eigen::Vector3d& t);

}  // namespace room_reverb::core
