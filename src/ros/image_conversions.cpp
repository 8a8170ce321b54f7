#include "room_reverb/ros/image_conversions.h"

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>

#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {

namespace enc = sensor_msgs::image_encodings;

cv::Mat cameraImageFromMessage(const sensor_msgs::Image& msg, const std::string& what) {
  if (msg.width == 0 || msg.height == 0) throw core::InputError(what + ": the image is empty");
  if (msg.step < msg.width || msg.data.size() < static_cast<std::size_t>(msg.step) * msg.height) {
    throw core::InputError(what + ": malformed image message (" + std::to_string(msg.data.size()) + " bytes for " +
                           std::to_string(msg.height) + " rows of " + std::to_string(msg.step) + ")");
  }
  std::string target;
  if (msg.encoding == enc::MONO8) {
    target = enc::MONO8;
  } else if (msg.encoding == enc::RGB8 || msg.encoding == enc::BGR8 || msg.encoding == enc::RGBA8 ||
             msg.encoding == enc::BGRA8) {
    target = enc::BGR8;
  } else {
    throw core::InputError(what + ": encoding '" + msg.encoding +
                           "' is not supported (use an 8-bit camera image: bgr8, rgb8, bgra8, rgba8 or mono8)");
  }
  try {
    return cv_bridge::toCvCopy(msg, target)->image;
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
