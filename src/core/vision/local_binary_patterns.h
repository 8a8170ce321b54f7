#pragma once
// Local binary patterns (Ojala, Pietikäinen and Mäenpää 2002) for the material features:
// the rotation-invariant uniform code ("riu2") of eight neighbours on a circle, which
// depends only on which neighbours are brighter than the centre, so a brightness gain
// (shading) leaves it unchanged.
#include <opencv2/core.hpp>

namespace room_reverb::core::material_detail {

constexpr int kLbpBins = 10;  // 0..8 neighbours brighter in one run, 9 for all other patterns

// Fractions of the region's pixels per code (bins sum to 1, or all 0 when no pixel of the
// region has its whole circle inside the image). `grey`: CV_32FC1; `mask`: CV_8UC1.
// A neighbour counts as brighter only when it exceeds the centre by a relative margin, so
// sensor noise on a flat surface gives the flat code rather than random patterns.
void lbpHistogram(const cv::Mat& grey, const cv::Mat& mask, double radius_px, float* bins);

}  // namespace room_reverb::core::material_detail
