#pragma once
// Filter-bank energies for the material features: Gaussian first and second derivatives
// at a few scales, steered to four orientations (Freeman and Adelson's steerable filters:
// the responses at any angle follow from the x, y and cross derivatives). Run on log
// brightness, so a brightness gain adds a constant that derivatives remove.
#include <opencv2/core.hpp>

namespace room_reverb::core::material_detail {

constexpr int kFilterScales = 3;                          // sigma 1, 2, 4 pixels
constexpr int kFilterEnergiesPerScale = 8;                // 4 first, then 4 second derivatives
constexpr int kFilterEnergies = kFilterScales * kFilterEnergiesPerScale;

// log(mean over the mask of the squared, scale-normalised response) for each filter, into
// `energies` (kFilterEnergies values). `log_grey`: CV_32FC1 whose pixels outside the mask
// hold something neutral (the region's mean), so the region's border is not an edge.
void filterBankEnergies(const cv::Mat& log_grey, const cv::Mat& mask, float* energies);

}  // namespace room_reverb::core::material_detail
