#include "room_reverb/common/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

void requireExistingFile(const std::string& path, const std::string& what, const std::string& hint) {
  struct stat status {};
  if (stat(path.c_str(), &status) != 0) {
    throw InputError(path + ": no such file (expected a " + what + ")" + (hint.empty() ? "" : "; " + hint));
  }
  if (S_ISDIR(status.st_mode)) throw InputError(path + ": is a directory, not a " + what);
}

std::string readTextFile(const std::string& path, const std::string& what) {
  requireExistingFile(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the " + what + " for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot open for writing");
  out << text;
  out.close();
  if (!out) throw InputError(path + ": write failed");
}

bool writeNewFileAtomically(const std::string& path, const std::string& text) {
  struct stat status {};
  if (::lstat(path.c_str(), &status) == 0) return false;
  const std::string part = path + ".part";
  const int file = ::open(part.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (file < 0 && errno == EEXIST) return false;
  if (file < 0) throw InputError(part + ": cannot create: " + std::strerror(errno));
  std::size_t written = 0;
  int error = 0;
  while (written < text.size() && error == 0) {
    const ssize_t n = ::write(file, text.data() + written, text.size() - written);
    if (n > 0) written += static_cast<std::size_t>(n);
    else if (errno != EINTR) error = errno;
  }
  if (error == 0 && ::fsync(file) != 0) error = errno;
  if (::close(file) != 0 && error == 0) error = errno;
  // link() rather than rename(): it refuses to replace a file that appeared meanwhile.
  if (error == 0 && ::link(part.c_str(), path.c_str()) != 0) error = errno;
  ::unlink(part.c_str());
  if (error == EEXIST) return false;
  if (error != 0) throw InputError(path + ": write failed: " + std::strerror(error));
  return true;
}

void createFolder(const std::string& path) {
  std::error_code error;
  std::filesystem::create_directories(path, error);
  if (!std::filesystem::is_directory(path)) {
    throw InputError(path + ": cannot create the folder" + (error ? ": " + error.message() : std::string()));
  }
}

std::string packageFilePath(const char* environment_variable, const std::string& relative) {
  const char* from_environment = std::getenv(environment_variable);
  if (from_environment != nullptr && *from_environment != '\0') return from_environment;
#ifdef ROOM_REVERB_SOURCE_DIR
  return std::string(ROOM_REVERB_SOURCE_DIR) + "/" + relative;
#else
  return relative;
#endif
}

}  // namespace room_reverb::core
