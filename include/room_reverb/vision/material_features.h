#pragma once
// Colour and texture features of an image region, for telling surface materials apart
// (vision/material_classifier.h) with hand-made features rather than a network's.
//
// The region is usually a rectified patch of a surface (vision/surface_materials.h): a
// fixed area of the surface seen face-on, rows along its vertical, so texture scale and
// orientation mean the same on every patch. The features are built to survive what the
// light does to a surface: a brightness gain that varies slowly across it (Lambert
// shading) and sensor noise. Only one entry (the mean brightness) keeps the absolute
// level; everything else is a ratio, a chromaticity or a pattern of signs.
//
// The vector, in order (all CV_32F):
//   [0]       mean grey level / 255                      (the one shading-dependent entry)
//   [1..4]    chromaticity r = R/(R+G+B), g = G/(R+G+B): mean r, mean g, std r, std g
//   [5..21]   hue-saturation histogram: one grey bin (saturation < 0.1), then 8 hues x
//             2 saturations (0.1-0.35, >= 0.35); fractions of the region
//   [22..29]  histogram of log(grey / mean grey) in 8 bins over [-0.5, 0.5] (ends open)
//   [30]      standard deviation of log grey (the texture's contrast)
//   [31..60]  rotation-invariant uniform local binary patterns (8 neighbours) at radii 1, 2
//             and 4 pixels, 10 bins each, fractions of the region
//   [61..84]  filter-bank energies of log grey: Gaussian first and second derivatives at
//             scales 1, 2, 4 pixels, each steered to 0, 45, 90, 135 degrees; log of the
//             mean squared, scale-normalised response
//   [85..86]  straight-line share: the fraction of the variance of log grey that survives
//             averaging along rows, and along columns (lines that cross the whole patch,
//             as the joints of tiles and bricks and the edges of planks do, keep theirs;
//             isotropic texture keeps about 1 / length); larger one first, so a floor's
//             heading does not matter
#include <opencv2/core.hpp>

namespace room_reverb::core {

constexpr int kMaterialFeatureLength = 87;
// Fewer pixels than this in the region say too little about its texture.
constexpr int kMinMaterialRegionPixels = 16;

// `bgr`: CV_8UC3; `mask`: CV_8UC1 of the same size, non-zero on the region's pixels, or
// empty for the whole image. Returns a 1 x kMaterialFeatureLength CV_32F row, every entry
// finite. InputError for an empty image, another image or mask type, a mask of another
// size, or fewer than kMinMaterialRegionPixels region pixels.
cv::Mat materialFeatures(const cv::Mat& bgr, const cv::Mat& mask = cv::Mat());

}  // namespace room_reverb::core
