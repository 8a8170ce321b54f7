// room_reverb simulate-worker: the other end of --workers and --worker-commands.
#include <iostream>
#include <unistd.h>

#include "arguments.h"
#include "command.h"
#include "room_reverb/acoustics/simulation_runner.h"

namespace room_reverb::tool {
namespace {

const char* kHelp = R"(usage: room_reverb simulate-worker

Simulates the jobs another room_reverb process sends on standard input (compare and
diagnose with --workers or --worker-commands) and answers each on standard output, until
its input ends. Each job carries its scene, positions and every setting, seed and thread
count included, so the answer is what the sender would have computed itself. Not for
interactive use: its input and output are binary frames (include/room_reverb/acoustics/
simulation_runner.h). Exits 0 at the end of its input, 2 for input that is not a job stream.
)";

int runSimulateWorker(const std::vector<std::string>& raw) {
  const Arguments args(raw, {}, {});
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  // Frames go to the original standard output; anything else the process prints goes to
  // standard error, so that no stray line can corrupt the stream.
  const int frames_out = ::dup(STDOUT_FILENO);
  if (frames_out < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
    std::cerr << "room_reverb simulate-worker: cannot set up its output\n";
    return 1;
  }
  const int status = core::serveSimulationJobs(STDIN_FILENO, frames_out);
  if (status == 2) std::cerr << "room_reverb simulate-worker: its input is not a stream of simulation jobs\n";
  return status;
}

const CommandRegistration registration({"simulate-worker", "simulate jobs sent by compare/diagnose --workers",
                                         kHelp, runSimulateWorker});

}  // namespace
}  // namespace room_reverb::tool
