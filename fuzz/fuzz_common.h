#pragma once
// Shared by the fuzz targets (see scripts/fuzz). A parser that rejects its input with a
// std::exception (InputError by the project's convention) has done its job; anything
// else, a crash, a sanitizer report, a hang or a non-std exception, is a finding, so no
// target catches more than std::exception.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <typeinfo>
#include <string>

#include "room_reverb/common/error.h"

namespace room_reverb_fuzz {

inline std::string text(const uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Set ROOM_REVERB_FUZZ_STRICT=1 to count only InputError as a clean rejection: another
// std::exception (std::out_of_range from a library, a yaml-cpp exception) is safe, yet
// reaches the user as a message the parser did not write. Read once per process.
inline bool strictRejections() {
  static const bool strict = std::getenv("ROOM_REVERB_FUZZ_STRICT") != nullptr;
  return strict;
}

// Runs `parse`, treating a thrown std::exception as a clean rejection.
template <typename Parse>
void expectCleanRejection(Parse&& parse) {
  try {
    parse();
  } catch (const room_reverb::core::InputError&) {
  } catch (const std::exception& e) {
    if (strictRejections()) {
      std::fprintf(stderr, "not an InputError (%s): %s\n", typeid(e).name(), e.what());
      std::abort();
    }
  }
}

// For readers that only take a path: the bytes in a file of this process, whose name
// ends in `extension` (the readers pick the format by it). One file per process and
// extension, rewritten on every input, so a long campaign leaves one file behind.
inline std::string writeInputFile(const uint8_t* data, std::size_t size, const std::string& extension) {
  const std::string path = "/tmp/room_reverb_fuzz_" + std::to_string(::getpid()) + extension;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) std::terminate();  // no place to write the input: not the parser's fault, stop loudly
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::terminate();
  std::fclose(file);
  return path;
}

}  // namespace room_reverb_fuzz
