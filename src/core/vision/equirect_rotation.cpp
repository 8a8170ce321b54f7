// Equirectangular rotation: one cv::remap over the image padded on the sphere.
#include "room_reverb/vision/equirect_rotation.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "equirect_padding.h"
#include "room_reverb/common/parallel_rows.h"
#include "rotation_check.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

void validate(const cv::Mat& image, const Eigen::Matrix3d& R, int interpolation) {
  if (image.empty()) throw InputError("rotateEquirect: the image is empty");
  if (image.cols != 2 * image.rows || image.cols < 2 * vision_detail::kEquirectPadPx) {
    std::ostringstream os;
    os << "rotateEquirect: an equirectangular image is twice as wide as high and at least "
       << 2 * vision_detail::kEquirectPadPx << " px wide; this one is " << image.cols << "x" << image.rows;
    throw InputError(os.str());
  }
  const int depth = image.depth();
  if ((depth != CV_8U && depth != CV_16U && depth != CV_32F) || image.channels() > 4) {
    throw InputError("rotateEquirect: the image must have 8-bit, 16-bit unsigned or float pixels with 1 to 4 channels");
  }
  vision_detail::requireRotation(R, "rotateEquirect");
  if (interpolation != cv::INTER_NEAREST && interpolation != cv::INTER_LINEAR && interpolation != cv::INTER_CUBIC &&
      interpolation != cv::INTER_LANCZOS4) {
    throw InputError("rotateEquirect: interpolation must be INTER_NEAREST, INTER_LINEAR, INTER_CUBIC or INTER_LANCZOS4");
  }
}

}  // namespace

cv::Mat rotateEquirect(const cv::Mat& image, const Eigen::Matrix3d& R, int interpolation) {
  validate(image, R, interpolation);
  const EquirectGeometry g{image.cols, image.rows};
  // The output pixel looking along e shows what the input saw along R^T e.
  const Eigen::Matrix3d output_to_input = R.transpose();
  // Pixel directions from per-column and per-row sines and cosines: a quarter of the
  // trigonometry of computing each pixel's direction afresh.
  std::vector<double> cos_azimuth(static_cast<std::size_t>(g.width)), sin_azimuth(cos_azimuth.size());
  for (int col = 0; col < g.width; ++col) {
    const double phi = equirectAzimuth(g, col);
    cos_azimuth[static_cast<std::size_t>(col)] = std::cos(phi);
    sin_azimuth[static_cast<std::size_t>(col)] = std::sin(phi);
  }
  cv::Mat map_x(g.height, g.width, CV_32FC1), map_y(g.height, g.width, CV_32FC1);
  if (std::abs(R(2, 2) - 1.0) < 1e-12) {
    // A turn about the pole (the levelling's yaw) keeps every row's elevation and moves
    // every column by the same azimuth: each column's source is worked out once, on the
    // horizon, and every row reads its own row.
    std::vector<float> source_x(static_cast<std::size_t>(g.width));
    for (int col = 0; col < g.width; ++col) {
      const auto c = static_cast<std::size_t>(col);
      source_x[c] = vision_detail::paddedRemapCoordinates(
                        g, output_to_input * Eigen::Vector3d(cos_azimuth[c], sin_azimuth[c], 0.0))
                        .x();
    }
    forEachRow(g.height, 0, [&](int row) {
      std::copy(source_x.begin(), source_x.end(), map_x.ptr<float>(row));
      std::fill_n(map_y.ptr<float>(row), g.width, static_cast<float>(row + vision_detail::kEquirectPadPx));
    });
  } else {
    forEachRow(g.height, 0, [&](int row) {
      const double theta = equirectElevation(g, row);
      const double cos_theta = std::cos(theta), sin_theta = std::sin(theta);
      float* mx = map_x.ptr<float>(row);
      float* my = map_y.ptr<float>(row);
      for (int col = 0; col < g.width; ++col) {
        const auto c = static_cast<std::size_t>(col);
        const Eigen::Vector3d direction(cos_theta * cos_azimuth[c], cos_theta * sin_azimuth[c], sin_theta);
        const Eigen::Vector2f p = vision_detail::paddedRemapCoordinates(g, output_to_input * direction);
        mx[col] = p.x();
        my[col] = p.y();
      }
    });
  }
  cv::Mat out;
  cv::remap(vision_detail::padEquirectOnSphere(image), out, map_x, map_y, interpolation, cv::BORDER_REPLICATE);
  return out;
}

}  // namespace room_reverb::core
