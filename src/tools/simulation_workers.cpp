#include "simulation_workers.h"

#include <sstream>
#include <vector>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/worker_process.h"

namespace room_reverb::tool {

using namespace room_reverb::core;

const char* const kSimulationWorkersHelp = R"(  --workers N        hand the simulations to N worker processes of this tool (default 0:
                     simulate in this process); the results are the same to the bit
  --worker-commands FILE
                     also start one worker per line of FILE (blank lines and # comments
                     skipped), each a shell command that runs `room_reverb simulate-worker`,
                     e.g. `ssh lab2 /opt/ros/.../room_reverb simulate-worker`
)";

std::set<std::string> simulationWorkerOptions() { return {"workers", "worker-commands"}; }

std::shared_ptr<SimulationRunner> simulationRunnerFrom(const Arguments& args) {
  const int local = args.intValue("workers", 0);
  if (local < 0 || local > 256) throw InputError("--workers must be 0 to 256");
  std::vector<std::string> commands;
  if (args.has("worker-commands")) {
    const std::string file = args.value("worker-commands", "");
    std::istringstream lines(readTextFile(file, "worker command list"));
    for (std::string line; std::getline(lines, line);) {
      const std::size_t first = line.find_first_not_of(" \t\r");
      if (first == std::string::npos || line[first] == '#') continue;
      commands.push_back(line.substr(first));
    }
    if (commands.empty()) throw InputError(file + ": no worker command in it (one shell command per line)");
  }
  if (local > 0) {
    for (const std::string& command : localWorkerCommands(local, executablePath())) commands.push_back(command);
  }
  if (commands.empty()) return nullptr;
  return std::make_shared<WorkerProcessSimulationRunner>(std::move(commands));
}

}  // namespace room_reverb::tool
