#pragma once
// Whole text files in and out, with the errors a user can cause reported as InputError.
#include <string>

namespace room_reverb::core {

// The file's contents. InputError naming the path for a missing file, a directory or an
// unreadable file; `what` says what the file was meant to be ("room model").
std::string readTextFile(const std::string& path, const std::string& what);

// Writes `text` (replacing the file). InputError naming the path when it cannot.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace room_reverb::core
