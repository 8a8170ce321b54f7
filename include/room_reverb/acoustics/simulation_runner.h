#pragma once
// Where a batch of simulations runs: in this process, in worker processes (on this
// machine, or on others through a command such as ssh), or on room_simulator nodes (the
// ROS layer's ServiceSimulationRunner). Every runner returns what simulateRoom returns for
// each request, to the bit: a request carries its seed and a fixed thread count, and a
// remote runner hands over the scene as resolved (simulation_wire.h). The diagnosis and the
// comparison take a runner, so their figures do not depend on where they ran.
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "room_reverb/acoustics/simulation_wire.h"
#include "room_reverb/common/parallel_rounds.h"

namespace room_reverb::core {

class SimulationRunner {
 public:
  virtual ~SimulationRunner() = default;
  // Result i is that of requests[i] in scenes[scene_of[i]]. When a request's input is
  // wrong (a source outside the room...), the InputError of the lowest such index is
  // thrown after every request has ended; a worker or node that fails is a
  // std::runtime_error. `wall_times_s` (may be null) gets each request's wall time where it
  // ran, transfer included.
  virtual std::vector<SimulationResult> simulateScenes(const std::vector<const AcousticScene*>& scenes,
                                                       const std::vector<SimulationRequest>& requests,
                                                       const std::vector<std::size_t>& scene_of,
                                                       std::vector<double>* wall_times_s) = 0;
  // Every request in one scene.
  std::vector<SimulationResult> simulate(const AcousticScene& scene, const std::vector<SimulationRequest>& requests,
                                         std::vector<double>* wall_times_s) {
    return simulateScenes({&scene}, requests, std::vector<std::size_t>(requests.size(), 0), wall_times_s);
  }
  // For reports: "this process", "2 worker processes", ...
  virtual std::string description() const = 0;
};

// This process: up to `parallel` requests at once, each with its own thread count
// (runInRounds' rounds give both).
class InProcessSimulationRunner : public SimulationRunner {
 public:
  explicit InProcessSimulationRunner(int parallel) : parallel_(parallel < 1 ? 1 : parallel) {}
  std::vector<SimulationResult> simulateScenes(const std::vector<const AcousticScene*>& scenes,
                                               const std::vector<SimulationRequest>& requests,
                                               const std::vector<std::size_t>& scene_of,
                                               std::vector<double>* wall_times_s) override;
  std::string description() const override { return "this process"; }

 private:
  int parallel_;
};

// A runner with a fixed number of slots (workers, nodes), each of which runs one encoded
// job at a time: jobs go to whichever slot is free, in order of their index.
class RemoteSimulationRunner : public SimulationRunner {
 public:
  // Batches from several threads run one after another (the slots are shared).
  std::vector<SimulationResult> simulateScenes(const std::vector<const AcousticScene*>& scenes,
                                               const std::vector<SimulationRequest>& requests,
                                               const std::vector<std::size_t>& scene_of,
                                               std::vector<double>* wall_times_s) override;

  // How the work came: batches run, jobs in them, the largest batch (for reports).
  struct Counts {
    std::size_t batches = 0;
    std::size_t jobs = 0;
    std::size_t largest_batch = 0;
  };
  Counts counts() const;

  // What a slot answers for one job.
  struct Reply {
    enum class Status { kResult, kInputError, kFailure } status = Status::kFailure;
    std::vector<std::uint8_t> result;  // kResult: encodeResult's bytes
    std::string message;               // otherwise: why
  };

 protected:
  virtual std::size_t slots() const = 0;
  // Runs `job` (encodeJob's bytes) on `slot`, blocking; called from one thread per slot.
  virtual Reply runOn(std::size_t slot, const std::vector<std::uint8_t>& job) = 0;

 private:
  mutable std::mutex batch_mutex_;
  Counts counts_;
};

// Frame kinds of the worker protocol (worker_process.h): a job, and the three replies.
constexpr std::uint8_t kJobFrame = 'J';
constexpr std::uint8_t kResultFrame = 'R';
constexpr std::uint8_t kInputErrorFrame = 'I';
constexpr std::uint8_t kFailureFrame = 'F';

// Worker processes started with the given command lines (each runs `room_reverb
// simulate-worker`, or anything that speaks its protocol), one slot each. They start on the
// first batch and end with the runner.
class WorkerProcessSimulationRunner : public RemoteSimulationRunner {
 public:
  explicit WorkerProcessSimulationRunner(std::vector<std::string> commands);
  ~WorkerProcessSimulationRunner() override;
  std::string description() const override;

 protected:
  std::size_t slots() const override { return commands_.size(); }
  Reply runOn(std::size_t slot, const std::vector<std::uint8_t>& job) override;

 private:
  struct Workers;
  std::vector<std::string> commands_;
  std::unique_ptr<Workers> workers_;
};

// What a worker does with jobs: decodes each (splitJob, decodeScene), simulates it
// (simulateRoom) and encodes the result. The scene of the last job is kept, so a batch of
// pairs in one scene builds it once. Throws InputError for a bad job and for what
// simulateRoom refuses.
class SimulationJobExecutor {
 public:
  std::vector<std::uint8_t> run(const std::uint8_t* job, std::size_t size);

 private:
  std::vector<std::uint8_t> scene_bytes_;
  std::unique_ptr<AcousticScene> scene_;
};

// `count` commands that start `room_reverb simulate-worker` from the tool at `tool_path`.
std::vector<std::string> localWorkerCommands(int count, const std::string& tool_path);

// The worker's side: reads job frames from `in_fd` until its input ends, answers each on
// `out_fd`; what `room_reverb simulate-worker` runs. Returns 0 at the end of input, 2 for
// input that is not a stream of frames.
int serveSimulationJobs(int in_fd, int out_fd);

}  // namespace room_reverb::core
