#pragma once
// Rotating an equirectangular image (vision/equirect.h) about the camera centre: the
// same panorama seen by a camera turned the other way, as used to level captures and
// turn them to the room's axes (vision/image_leveling.h).
#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace room_reverb::core {

// Resamples `image` so that the scene seen along direction d in the input's camera frame
// appears along R d in the output's (R: input frame -> output frame, orthonormal with
// determinant +1); the output has the input's size and type.
//
// `interpolation` is cv::INTER_NEAREST (label and id images: no blends of two labels),
// cv::INTER_LINEAR, cv::INTER_CUBIC or cv::INTER_LANCZOS4. Samples are taken on the
// sphere: across the +-180 degree seam from the other edge's columns, and across a pole
// from the row on the opposite azimuth, so neither leaves a line of border pixels. A
// rotation about z by a whole number of pixel angles (2 pi / W) is an exact column shift.
// Interpolating an image holding +inf (the sky of a range image) spreads inf or NaN into
// the neighbouring pixels: use nearest there.
//
// InputError for: an empty image, one that is not 2:1 (width = 2 x height) or narrower
// than 8 px, a depth other than 8U, 16U or 32F or more than 4 channels, a matrix that is
// not a rotation (|R^T R - I| or |det R - 1| over 1e-6, or not finite), another
// interpolation.
cv::Mat rotateEquirect(const cv::Mat& image, const Eigen::Matrix3d& R, int interpolation);

}  // namespace room_reverb::core
