#pragma once
// Error types of the core library.
//
// InputError is what a user can cause (a missing file, a wrong channel count, NaN
// samples...). Its message says what was wrong and, where it helps, what to do; tools
// print it as one line and exit 2, services answer success=false with it.
#include <cstddef>
#include <stdexcept>
#include <string>

namespace room_reverb::core {

// A message made safe to print as one line: control characters (a newline, an escape
// sequence quoted from a corrupt file) and bytes that are not UTF-8 become \n, \t, \xNN;
// valid UTF-8 (a path with accents) stays; past `max_bytes` the text is cut and says how
// much was left out.
std::string printableLine(const std::string& text, std::size_t max_bytes = 600);

class InputError : public std::runtime_error {
 public:
  // The message is stored as printableLine(what): it often quotes the bad input.
  explicit InputError(const std::string& what) : std::runtime_error(printableLine(what)) {}
};

}  // namespace room_reverb::core
