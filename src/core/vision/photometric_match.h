#pragma once
// Two cameras on auto-exposure record the same room with different gains and white
// balances. Semi-global matching loses pixels to it (a third of a stop between the
// cameras leaves 80 % of the meeting room's pixels with a range instead of 98 %), and the
// sub-pixel refinement compares grey levels directly, so a gain between the images
// becomes a bias in the disparity. Two maps, each an affine map per channel that carries
// the bottom image's grey levels onto the top's:
//   - before matching, from the two images' grey-level quantiles: no correspondences
//     needed, and close enough for the matcher, but 0.2 m apart the two views see the
//     floor and ceiling in different proportions, so on a pair with no exposure
//     difference at all this map is 2-4 % off in gain;
//   - before the refinement, from the pixel pairs the matcher found, which show the same
//     surface points.
// (Measured on rendered cluttered rooms: the first map before the refinement raises the
// median range error on walls of an ideal pair from 0.75 % to 0.95 %; the second leaves
// it at 0.75 % and brings a pair a third of a stop apart from 1.42 % to 0.82 %.)
#include <opencv2/core.hpp>

namespace room_reverb::core {

// Per channel: bottom_matched = gain * bottom + offset.
struct PhotometricMap {
  cv::Vec3d gain{1.0, 1.0, 1.0};
  cv::Vec3d offset{0.0, 0.0, 0.0};
};

// The map that carries the bottom image's grey-level quantiles (2nd to 98th percentile,
// over the rows outside the polar caps of `polar_cap_deg`, levels 0 and 255 left out as
// clipped) onto the top's, by least squares.
PhotometricMap photometricMapFromQuantiles(const cv::Mat& top, const cv::Mat& bottom, double polar_cap_deg);

// The map fitted by least squares on the pixel pairs top(row, col) and bottom(row - d,
// col) for the disparity d [px] of `disparity_px` (CV_32FC1, the top image's grid, NaN
// where there is none), every `step`-th row and column, leaving out pairs with a level
// clipped at 0 or 255 and then the fifth of pairs that fit worst (mismatches, edges). A
// channel with too few pairs, or whose fit would invert or crush it, keeps gain 1 and
// offset 0. 8-bit images of one size with 1 or 3 channels.
PhotometricMap photometricMapFromMatches(const cv::Mat& top, const cv::Mat& bottom, const cv::Mat& disparity_px, int step = 2);

// `bottom` through the map, rounded and clipped to 8 bits.
cv::Mat applyPhotometricMap(const cv::Mat& bottom, const PhotometricMap& map);

}  // namespace room_reverb::core
