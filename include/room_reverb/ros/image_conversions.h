#pragma once
// sensor_msgs/Image to and from the OpenCV images of the visual route.
#include <sensor_msgs/Image.h>

#include <opencv2/core.hpp>
#include <string>

namespace room_reverb::ros_bridge {

// An 8-bit colour or grey camera image as the core takes it: bgr8 for colour encodings
// (rgb8, bgr8, rgba8, bgra8), mono8 for mono8. core::InputError naming `what` for an empty
// image, another encoding (16-bit, float, Bayer) or a malformed message (data shorter than
// step x height, or step shorter than a row of pixels).
cv::Mat cameraImageFromMessage(const sensor_msgs::Image& msg, const std::string& what);

// The checks of cameraImageFromMessage without the conversion: for an image that is kept
// to be converted later.
void checkCameraImageMessage(const sensor_msgs::Image& msg, const std::string& what);

// A range image (32FC1, metres) as CV_32FC1. InputError naming `what` for an empty or
// malformed message or another encoding.
cv::Mat rangeImageFromMessage(const sensor_msgs::Image& msg, const std::string& what);

// A copy of `image` as a message with the given header; `encoding` is a
// sensor_msgs::image_encodings name matching the image's type (bgr8, mono8, 32FC1...).
sensor_msgs::Image imageToMessage(const cv::Mat& image, const std::string& encoding, const std_msgs::Header& header);

}  // namespace room_reverb::ros_bridge
