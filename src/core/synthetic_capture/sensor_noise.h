#pragma once
// What the sensor and the encoder do to the capture generator's float images: exposure
// and white balance, noise, clipping and quantisation, JPEG compression.
#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>

namespace room_reverb::core::capture_detail {

// CV_32FC3 (grey levels, any range) -> CV_8UC3 with zero-mean Gaussian noise of `sigma`
// grey levels added before rounding. The noise of pixel (row, col, channel) is a hash of
// (seed, stream, row, col, channel), so it is reproducible and independent of threading;
// `stream` keeps the two cameras' (and the fisheye images') noise independent.
// CV_32FC3 BGR times `gain` and the per-channel `white_balance_rgb` (R, G, B order).
cv::Mat exposed(const cv::Mat& color, double gain, const Eigen::Vector3d& white_balance_rgb);

cv::Mat quantizeWithNoise(const cv::Mat& color, double sigma, std::uint64_t seed, std::uint64_t stream);

// A CV_8UC3 image encoded as JPEG at `quality` (1..100) and decoded again.
cv::Mat jpegRoundTrip(const cv::Mat& image, int quality);

}  // namespace room_reverb::core::capture_detail
