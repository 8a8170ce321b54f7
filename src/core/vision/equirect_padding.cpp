#include "equirect_padding.h"

#include <vector>

namespace room_reverb::core::vision_detail {

cv::Mat padEquirectOnSphere(const cv::Mat& image) {
  const int w = image.cols, h = image.rows;
  cv::Mat wrapped, half_turn, half_turn_wrapped;
  cv::copyMakeBorder(image, wrapped, 0, 0, kEquirectPadPx, kEquirectPadPx, cv::BORDER_WRAP);
  cv::hconcat(image.colRange(w / 2, w), image.colRange(0, w / 2), half_turn);
  cv::copyMakeBorder(half_turn, half_turn_wrapped, 0, 0, kEquirectPadPx, kEquirectPadPx, cv::BORDER_WRAP);
  cv::Mat above, below, padded;
  cv::flip(half_turn_wrapped.rowRange(0, kEquirectPadPx), above, 0);
  cv::flip(half_turn_wrapped.rowRange(h - kEquirectPadPx, h), below, 0);
  cv::vconcat(std::vector<cv::Mat>{above, wrapped, below}, padded);
  return padded;
}

Eigen::Vector2f paddedRemapCoordinates(const EquirectGeometry& g, const Eigen::Vector3d& d) {
  // Continuous coordinates put pixel centres at i + 0.5; OpenCV puts them at i.
  const Eigen::Vector2d uv = equirectCoordinates(g, d);
  return {static_cast<float>(uv.x() - 0.5 + kEquirectPadPx), static_cast<float>(uv.y() - 0.5 + kEquirectPadPx)};
}

}  // namespace room_reverb::core::vision_detail
