#include "room_reverb/ros/image_conversions.h"

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>

#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {

namespace enc = sensor_msgs::image_encodings;

namespace {

// The encoding cv_bridge converts a camera encoding to; "" for one the core cannot use.
std::string cameraTarget(const std::string& encoding) {
  if (encoding == enc::MONO8) return enc::MONO8;
  if (encoding == enc::RGB8 || encoding == enc::BGR8 || encoding == enc::RGBA8 || encoding == enc::BGRA8) return enc::BGR8;
  return "";
}

}  // namespace

void checkCameraImageMessage(const sensor_msgs::Image& msg, const std::string& what) {
  if (msg.width == 0 || msg.height == 0) throw core::InputError(what + ": the image is empty");
  if (cameraTarget(msg.encoding).empty()) {
    throw core::InputError(what + ": encoding '" + msg.encoding +
                           "' is not supported (use an 8-bit camera image: bgr8, rgb8, bgra8, rgba8 or mono8)");
  }
  // Every supported encoding has one byte per channel.
  const std::size_t row_bytes = static_cast<std::size_t>(msg.width) * enc::numChannels(msg.encoding);
  if (msg.step < row_bytes || msg.data.size() < static_cast<std::size_t>(msg.step) * msg.height) {
    throw core::InputError(what + ": malformed image message (" + std::to_string(msg.data.size()) + " bytes for " +
                           std::to_string(msg.height) + " rows of " + std::to_string(msg.step) + ", " +
                           std::to_string(row_bytes) + " bytes of pixels a row)");
  }
}

cv::Mat cameraImageFromMessage(const sensor_msgs::Image& msg, const std::string& what) {
  checkCameraImageMessage(msg, what);
  try {
    return cv_bridge::toCvCopy(msg, cameraTarget(msg.encoding))->image;
  } catch (const cv_bridge::Exception& e) {
    throw core::InputError(what + ": " + e.what());
  } catch (const cv::Exception& e) {
    throw core::InputError(what + ": " + e.msg);
  }
}

cv::Mat rangeImageFromMessage(const sensor_msgs::Image& msg, const std::string& what) {
  if (msg.width == 0 || msg.height == 0) throw core::InputError(what + ": the image is empty");
  if (msg.encoding != enc::TYPE_32FC1) {
    throw core::InputError(what + ": encoding '" + msg.encoding + "' is not a range image (use 32FC1, metres)");
  }
  if (msg.step < 4 * msg.width || msg.data.size() < static_cast<std::size_t>(msg.step) * msg.height) {
    throw core::InputError(what + ": malformed image message (" + std::to_string(msg.data.size()) + " bytes for " +
                           std::to_string(msg.height) + " rows of " + std::to_string(msg.step) + ")");
  }
  try {
    return cv_bridge::toCvCopy(msg, enc::TYPE_32FC1)->image;
  } catch (const cv_bridge::Exception& e) {
    throw core::InputError(what + ": " + e.what());
  }
}

sensor_msgs::Image imageToMessage(const cv::Mat& image, const std::string& encoding, const std_msgs::Header& header) {
  sensor_msgs::Image msg;
  cv_bridge::CvImage(header, encoding, image).toImageMsg(msg);
  return msg;
}

}  // namespace room_reverb::ros_bridge
