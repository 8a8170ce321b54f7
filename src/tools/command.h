#pragma once
// Subcommands of the `room_reverb` tool. Each registers itself with a name, a one-line
// summary and a function that runs it on the arguments after the subcommand's name.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace room_reverb::tool {

// Thrown for a wrong command line; main() prints it with a hint to --help and exits 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Command {
  std::string name;
  std::string summary;
  std::string help;  // full --help text
  std::function<int(const std::vector<std::string>&)> run;
};

std::vector<Command>& commandRegistry();

struct CommandRegistration {
  explicit CommandRegistration(Command command) { commandRegistry().push_back(std::move(command)); }
};

}  // namespace room_reverb::tool
