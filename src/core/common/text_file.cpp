#include "room_reverb/common/text_file.h"

#include <sys/stat.h>

#include <fstream>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

std::string readTextFile(const std::string& path, const std::string& what) {
  struct stat status {};
  if (stat(path.c_str(), &status) != 0) throw InputError(path + ": no such file (expected a " + what + ")");
  if (S_ISDIR(status.st_mode)) throw InputError(path + ": is a directory, not a " + what);
  std::ifstream in(path);
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

}  // namespace room_reverb::core
