#include "image_files.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "room_reverb/common/error.h"

namespace room_reverb::tool {
namespace {

// The image codecs OpenCV calls write their own diagnostics to stderr (libpng prints
// "libpng error: bad adaptive filter value" before OpenCV returns an empty image), which
// would put a second line beside the tool's one-line error. While a file is decoded, fd 2
// goes to a temporary file; what the codec said is returned for the error message.
class CodecMessages {
 public:
  CodecMessages() : file_(std::tmpfile()) {
    std::fflush(stderr);
    if (file_ != nullptr) saved_ = dup(STDERR_FILENO);
    if (saved_ >= 0 && dup2(fileno(file_), STDERR_FILENO) < 0) {
      close(saved_);
      saved_ = -1;
    }
  }
  ~CodecMessages() {
    restore();
    if (file_ != nullptr) std::fclose(file_);
  }
  CodecMessages(const CodecMessages&) = delete;
  CodecMessages& operator=(const CodecMessages&) = delete;

  // Puts stderr back and returns the codec's last line ("" when it said nothing).
  std::string finish() {
    restore();
    if (file_ == nullptr) return "";
    std::string text;
    std::rewind(file_);
    char buffer[512];
    while (std::fgets(buffer, sizeof buffer, file_) != nullptr) text += buffer;
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    const auto last = text.find_last_of('\n');
    return last == std::string::npos ? text : text.substr(last + 1);
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    dup2(saved_, STDERR_FILENO);
    close(saved_);
    saved_ = -1;
  }
  std::FILE* file_;
  int saved_ = -1;
};

}  // namespace

cv::Mat readImage(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw core::InputError(path + ": no such image file");
  cv::Mat image;
  std::string said;
  try {
    CodecMessages messages;
    image = cv::imread(path, cv::IMREAD_UNCHANGED);
    said = messages.finish();
  } catch (const cv::Exception& e) {
    throw core::InputError(path + ": cannot read the image (" + e.msg + ")");
  }
  if (image.empty()) {
    throw core::InputError(path + ": not an image OpenCV can read" + (said.empty() ? "" : " (" + said + ")"));
  }
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
