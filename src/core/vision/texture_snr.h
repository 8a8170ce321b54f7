#pragma once
// Where an image's texture is too faint for its sensor noise to be matched. A stereo
// matcher finds a disparity wherever it is asked; on a plain painted wall under the noise
// of a dim room the grey levels it compares are mostly noise, and semi-global matching
// then returns smooth, confident and wrong disparities (the plain office's gypsum wall
// drawn with 2 grey levels of noise: 100 % of its pixels ranged, median error 10 %). A
// layout fitted to those points finds no wall, or finds it in the wrong place. What a
// window can be matched on is the energy of its grey-level gradient along the epipolar
// line; sensor noise adds a known share to it. Their ratio says whether the window holds
// texture at all.
#include <opencv2/core.hpp>

#include "subpixel_disparity.h"

namespace room_reverb::core::stereo_detail {

// The standard deviation [grey levels] of an image's pixel noise, from the response to
// the mask [1 -2 1; -2 4 -2; 1 -2 1], which cancels a locally planar image (Immerkaer,
// "Fast noise variance estimation", CVIU 1996). The median of the response's magnitude
// (scaled to sigma for Gaussian noise: 1.4826 / 6, the mask's norm being 6) keeps edges and
// texture, which lie in the response's tail, from inflating it. grey: CV_32FC1.
double pixelNoiseSigma(const cv::Mat& grey);

// Per pixel of `image` (the transposed image, rows along the epipolar line), the
// signal-to-noise ratio of the epipolar slope's energy over a (2 half_window + 1)^2
// window: mean(dx^2) / (sigma^2 / 2) - 1, sigma^2 / 2 being what pixel noise of standard
// deviation sigma = noise_sigma alone gives the central difference
// dx = (g[c+1] - g[c-1]) / 2. 0: no texture beyond the noise. CV_32FC1 of the transposed
// image's size.
cv::Mat epipolarTextureSnr(const EpipolarImage& image, double noise_sigma, int half_window);

}  // namespace room_reverb::core::stereo_detail
