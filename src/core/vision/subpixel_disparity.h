#pragma once
// Sub-pixel refinement of a stereo matcher's disparities. Semi-global matching finds the
// disparity to a sixteenth of a pixel by fitting a parabola to three matching costs, which
// pulls results towards whole pixels ("pixel locking", Shimizu and Okutomi 2005): about a
// tenth of a pixel of error. With a vertical 0.2 m baseline a point 8 m away on the
// horizon is 8 pixels of disparity at 2048 x 1024, so that tenth is over 1 % of its range.
// Gauss-Newton on the grey levels of a small window (Lucas and Kanade's step, in one
// dimension along the epipolar line) removes the locking: it moves the disparity to the
// minimum of the window's squared difference with the other image interpolated between
// pixels.
#include <opencv2/core.hpp>

namespace room_reverb::core::stereo_detail {

// Grey levels (CV_32FC1) of an 8-bit image, and their derivative along the rows.
struct EpipolarImage {
  cv::Mat grey;
  cv::Mat dx;
};
EpipolarImage epipolarImage(const cv::Mat& image);

// The disparity d (pixels, left(x) matching right(x - d)) that minimises the squared grey
// difference over the (2 half_rows + 1) x (2 half_cols + 1) window centred on (row, col)
// of `left`, starting from d0. Returns d0 unchanged where the window leaves the image, the
// window has too little texture along the rows, or the step would move more than half a
// pixel from d0 (a different minimum: the matcher's choice stands).
double refineDisparity(const EpipolarImage& left, const EpipolarImage& right, int row, int col, double d0, int half_rows,
                       int half_cols);

}  // namespace room_reverb::core::stereo_detail
