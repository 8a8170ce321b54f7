#pragma once
// Sensor noise and quantisation of the capture generator's float images.
#include <cstdint>
#include <opencv2/core.hpp>

namespace room_reverb::core::capture_detail {

// CV_32FC3 (grey levels, any range) -> CV_8UC3 with zero-mean Gaussian noise of `sigma`
// grey levels added before rounding. The noise of pixel (row, col, channel) is a hash of
// (seed, stream, row, col, channel), so it is reproducible and independent of threading;
// `stream` keeps the two cameras' (and the fisheye images') noise independent.
cv::Mat quantizeWithNoise(const cv::Mat& color, double sigma, std::uint64_t seed, std::uint64_t stream);

}  // namespace room_reverb::core::capture_detail
