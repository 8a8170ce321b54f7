#include "subpixel_disparity.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace room_reverb::core::stereo_detail {
namespace {

constexpr int kIterations = 3;
// Below this mean squared gradient [grey levels^2 per pixel^2] the window is too plain for
// the step to mean anything (sensor noise alone gives a few).
constexpr double kMinGradientEnergy = 4.0;
// A step below this [px] ends the iterations: the next would move the disparity by less
// than a thousandth of a pixel, 0.01 % of the range of a wall 8 m away at 2048 x 1024.
constexpr double kConverged = 0.005;
// Window columns summed lane by lane (below), this many at a time.
constexpr int kMaxLanes = 16;

}  // namespace

EpipolarImage epipolarImage(const cv::Mat& image) {
  EpipolarImage out;
  cv::Mat grey8;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey8, cv::COLOR_BGR2GRAY);
  } else {
    grey8 = image;
  }
  grey8.convertTo(out.grey, CV_32F);
  out.dx = cv::Mat::zeros(out.grey.size(), CV_32F);
  for (int r = 0; r < out.grey.rows; ++r) {
    const float* g = out.grey.ptr<float>(r);
    float* d = out.dx.ptr<float>(r);
    for (int c = 1; c + 1 < out.grey.cols; ++c) d[c] = 0.5f * (g[c + 1] - g[c - 1]);
  }
  return out;
}

double refineDisparity(const EpipolarImage& left, const EpipolarImage& right, int row, int col, double d0, int half_rows,
                       int half_cols) {
  const int cols = left.grey.cols;
  if (row - half_rows < 0 || row + half_rows >= left.grey.rows) return d0;
  if (col - half_cols < 0 || col + half_cols >= cols) return d0;
  // Every sample of the right image must stay inside it for a move of up to a pixel.
  if (col - half_cols - d0 - 2.0 < 0.0 || col + half_cols - d0 + 2.0 >= cols) return d0;
  double d = d0;
  const int width = 2 * half_cols + 1;
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    const double x0 = -d;  // right-image position of left column c is c - d
    const double base = std::floor(x0);
    const double a = x0 - base;
    const int shift = static_cast<int>(base);
    // One single-precision lane per window column, summed down the rows and then across
    // the lanes, in blocks of kMaxLanes columns: the lanes are independent, so the
    // compiler takes them four or eight at a time, where one running double sum would
    // take the terms one by one (the grey levels are 8-bit; a lane sums at most
    // 2 half_rows + 1 terms).
    const auto wa = static_cast<float>(a), wb = static_cast<float>(1.0 - a);
    double num = 0.0, den = 0.0;
    for (int block = 0; block < width; block += kMaxLanes) {
      const int lanes = std::min(kMaxLanes, width - block);
      std::array<float, kMaxLanes> lane_num{}, lane_den{};
      const int first = col - half_cols + block;
      for (int r = row - half_rows; r <= row + half_rows; ++r) {
        const float* l = left.grey.ptr<float>(r) + first;
        const float* g = right.grey.ptr<float>(r) + first + shift;
        const float* gx = right.dx.ptr<float>(r) + first + shift;
        for (int j = 0; j < lanes; ++j) {
          const float value = wb * g[j] + wa * g[j + 1];
          const float slope = wb * gx[j] + wa * gx[j + 1];
          lane_num[static_cast<std::size_t>(j)] += (l[j] - value) * slope;
          lane_den[static_cast<std::size_t>(j)] += slope * slope;
        }
      }
      for (int j = 0; j < lanes; ++j) num += lane_num[static_cast<std::size_t>(j)], den += lane_den[static_cast<std::size_t>(j)];
    }
    const double samples = (2.0 * half_rows + 1.0) * (2.0 * half_cols + 1.0);
    if (den < kMinGradientEnergy * samples) return d0;
    // r(d) = L - R(c - d); dr/dd = R'(c - d); step = -sum(r r') / sum(r'^2).
    const double step = num / den;
    d -= step;
    if (std::abs(d - d0) > 0.5) return d0;
    if (std::abs(step) < kConverged) break;
  }
  return d;
}

}  // namespace room_reverb::core::stereo_detail
