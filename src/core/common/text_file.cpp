#include "room_reverb/common/text_file.h"

#include <sys/stat.h>

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
