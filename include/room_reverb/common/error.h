#pragma once
// Error types of the core library.
//
// InputError is what a user can cause (a missing file, a wrong channel count, NaN
// samples...). Its message says what was wrong and, where it helps, what to do; tools
// print it as one line and exit 2, services answer success=false with it.
#include <stdexcept>
#include <string>

namespace room_reverb::core {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace room_reverb::core
