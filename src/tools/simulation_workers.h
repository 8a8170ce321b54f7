#pragma once
// The options that hand a command's simulations to worker processes (compare, diagnose):
// --workers N local processes of this tool, --worker-commands FILE for workers started by
// other commands (one per line: e.g. `ssh lab2 room_reverb simulate-worker`).
#include <memory>
#include <set>
#include <string>

#include "arguments.h"
#include "room_reverb/acoustics/simulation_runner.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/worker_process.h"

namespace room_reverb::tool {

extern const char* const kSimulationWorkersHelp;
std::set<std::string> simulationWorkerOptions();

// The runner the options ask for; null (this process) when they ask for none.
std::shared_ptr<core::SimulationRunner> simulationRunnerFrom(const Arguments& args);

// `run()`, with a worker that fails (core::WorkerFailure: a command of the user's that does
// not start, dies or speaks no frames) reported as the user's error: one line, exit 2.
template <typename Run>
auto reportingWorkerFailures(Run&& run) -> decltype(run()) {
  try {
    return run();
  } catch (const core::WorkerFailure& e) {
    throw core::InputError(e.what());
  }
}

}  // namespace room_reverb::tool
