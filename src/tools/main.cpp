// room_reverb: the command-line twin of the project's nodes. Usage:
//   room_reverb SUBCOMMAND [ARGS...]     room_reverb SUBCOMMAND --help
// Exit codes: 0 success, 2 bad input or usage (one line on stderr), 1 internal error.
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "command.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/memory_reuse.h"

namespace room_reverb::tool {

std::vector<Command>& commandRegistry() {
  static std::vector<Command> commands;
  return commands;
}

namespace {

void printOverview(std::ostream& out) {
  out << "usage: room_reverb SUBCOMMAND [ARGS...]\n\nsubcommands:\n";
  for (const auto& command : commandRegistry()) {
    out << "  " << command.name << std::string(command.name.size() < 14 ? 14 - command.name.size() : 1, ' ')
        << command.summary << "\n";
  }
  out << "\n'room_reverb SUBCOMMAND --help' describes one.\n";
}

}  // namespace
}  // namespace room_reverb::tool

int main(int argc, char** argv) {
  room_reverb::core::keepFreedMemoryForReuse();
  using namespace room_reverb::tool;
  using room_reverb::core::printableLine;
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    printOverview(args.empty() ? std::cerr : std::cout);
    return args.empty() ? 2 : 0;
  }
  const std::string name = args[0];
  for (const auto& command : commandRegistry()) {
    if (command.name != name) continue;
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    for (const auto& arg : rest) {
      if (arg == "--help" || arg == "-h") {
        std::cout << command.help;
        return 0;
      }
    }
    try {
      return command.run(rest);
    } catch (const UsageError& e) {
      std::cerr << "room_reverb " << name << ": " << printableLine(e.what()) << " (see room_reverb " << name
                << " --help)\n";
      return 2;
    } catch (const room_reverb::core::InputError& e) {
      std::cerr << "room_reverb " << name << ": " << e.what() << "\n";  // already one line
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "room_reverb " << name << ": internal error: " << printableLine(e.what()) << "\n";
      return 1;
    }
  }
  std::cerr << "room_reverb: unknown subcommand '" << printableLine(name, 80) << "' (see room_reverb --help)\n";
  return 2;
}
