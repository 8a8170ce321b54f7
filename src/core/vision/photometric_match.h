#pragma once
// Two cameras on auto-exposure record the same room with different gains and white
// balances. Semi-global matching loses pixels to it (a third of a stop between the
// cameras leaves 80 % of the meeting room's pixels with a range instead of 98 %), and the
// sub-pixel refinement compares grey levels directly, so a gain between the images
// becomes a bias in the disparity. The matcher's own pairs (most of them right even then)
// say which pixels of the two images show the same surface point; a gain and an offset
// per channel fitted on them carry the bottom image's grey levels onto the top's, and the
// pair is matched with them (spherical_stereo.cpp fits the map on a match of the pair at
// half size, which keeps a gain and an offset, so the full-size match runs once). The matcher is sensitive even to small differences: on the
// meeting room at 2048 x 1024 a shift of 2-4 grey levels loses 13 % of the ranges nearer
// than 1.5 m, which is why a map from the two images' histograms is no substitute (the
// two views, 0.2 m apart, see the floor and ceiling in different proportions, and such a
// map is off by that much on a pair exposed alike, where the map from the pairs is
// within 0.15 grey levels of no change).
#include <opencv2/core.hpp>

namespace room_reverb::core {

// Per channel: bottom_matched = gain * bottom + offset.
struct PhotometricMap {
  cv::Vec3d gain{1.0, 1.0, 1.0};
  cv::Vec3d offset{0.0, 0.0, 0.0};
};

// The map fitted by least squares on the pixel pairs top(row, col) and bottom(row - d,
// col) for the disparity d [px] of `disparity_px` (CV_32FC1, the top image's grid, NaN
// where there is none), every `step`-th row and column, leaving out pairs with a level
// clipped at 0 or 255 and then the fifth of pairs that fit worst (mismatches, edges). A
// channel with too few pairs, or whose fit would invert or crush it, keeps gain 1 and
// offset 0. 8-bit images of one size with 1 or 3 channels.
PhotometricMap photometricMapFromMatches(const cv::Mat& top, const cv::Mat& bottom, const cv::Mat& disparity_px, int step = 4);

// The most the map moves a grey level between 32 and 224, in any channel.
double largestLevelChange(const PhotometricMap& map);
// Above this many grey levels the cameras are taken to be exposed differently.
constexpr double kExposureDifference = 1.0;

// `bottom` through the map, rounded and clipped to 8 bits.
cv::Mat applyPhotometricMap(const cv::Mat& bottom, const PhotometricMap& map);

}  // namespace room_reverb::core
