#include "test_files.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "room_reverb/common/error.h"

namespace room_reverb::test {

std::filesystem::path tempPath(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("room_reverb_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

std::string writeFile(const std::string& name, const std::string& contents) {
  const auto path = tempPath(name);
  std::ofstream(path, std::ios::binary) << contents;
  return path.string();
}

void expectInputError(const std::function<void()>& call, const std::vector<std::string>& fragments) {
  try {
    call();
    ADD_FAILURE() << "expected an InputError mentioning '" << (fragments.empty() ? "" : fragments.front()) << "'";
  } catch (const core::InputError& e) {
    for (const auto& fragment : fragments) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << "'" << fragment << "' not in: " << e.what();
    }
  }
}

}  // namespace room_reverb::test
