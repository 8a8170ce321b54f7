#pragma once
// Sampling an equirectangular image at arbitrary directions with cv::remap: the image
// padded with the pixels that surround it on the sphere, and the remap coordinates of a
// direction in the padded image. Shared by everything that resamples a panorama (rotation,
// perspective views), so none of them leaves a line of border pixels at the seam or the
// poles.
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "room_reverb/vision/equirect.h"

namespace room_reverb::core::vision_detail {

// Pixels added on every side: enough for every remap interpolation (Lanczos-4 reads 3
// pixels before the sample and 4 after it).
constexpr int kEquirectPadPx = 4;

// The image (width >= 2 kEquirectPadPx, height = width / 2) with kEquirectPadPx pixels of
// its sphere around it: left and right, the columns from the other side of the +-180
// degree seam; above the zenith (below the nadir), the rows just past the pole, which are
// the first (last) rows half a turn round in azimuth, in mirrored order.
cv::Mat padEquirectOnSphere(const cv::Mat& image);

// Where cv::remap reads direction d (need not be unit) in padEquirectOnSphere's output of
// an image of geometry g (OpenCV's convention: the centre of pixel i at i).
Eigen::Vector2f paddedRemapCoordinates(const EquirectGeometry& g, const Eigen::Vector3d& d);

}  // namespace room_reverb::core::vision_detail
