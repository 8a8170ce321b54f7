#pragma once
// Image files for the tool's visual-route commands, with errors that name the file.
#include <opencv2/core.hpp>
#include <string>

namespace room_reverb::tool {

// cv::imread unchanged (8-bit colour stays BGR, 16-bit ids stay 16-bit); InputError for a
// missing or unreadable file.
cv::Mat readImage(const std::string& path);
// cv::imwrite; InputError when the file cannot be written (folder missing, unknown extension).
void writeImage(const std::string& path, const cv::Mat& image);

}  // namespace room_reverb::tool
