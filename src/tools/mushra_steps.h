#pragma once
// The steps of `room_reverb mushra` that live in their own files, for mushra_command.cpp's
// step table and help text.
#include <string>
#include <vector>

namespace room_reverb::tool {

// `room_reverb mushra make --plan PLAN.yaml --out DIR`.
extern const char* const kMushraMakeHelp;
int runMushraMake(const std::vector<std::string>& args);

// `room_reverb mushra serve DIR [--port N] [--host H]` (mushra_serve_command.cpp).
extern const char* const kMushraServeHelp;
int runMushraServe(const std::vector<std::string>& args);

}  // namespace room_reverb::tool
