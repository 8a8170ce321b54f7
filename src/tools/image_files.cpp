#include "image_files.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "room_reverb/common/error.h"

namespace room_reverb::tool {

cv::Mat readImage(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw core::InputError(path + ": no such image file");
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw core::InputError(path + ": cannot read the image (" + e.msg + ")");
  }
  if (image.empty()) throw core::InputError(path + ": not an image OpenCV can read");
  return image;
}

void writeImage(const std::string& path, const cv::Mat& image) {
  bool written = false;
  try {
    written = cv::imwrite(path, image);
  } catch (const cv::Exception& e) {
    throw core::InputError(path + ": cannot write the image (" + e.msg + ")");
  }
  if (!written) throw core::InputError(path + ": cannot write the image");
}

}  // namespace room_reverb::tool
