#include "room_reverb/acoustics/simulation_runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <exception>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "room_reverb/common/error.h"
#include "room_reverb/common/worker_process.h"

namespace room_reverb::core {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void requireSceneIndices(std::size_t scenes, const std::vector<SimulationRequest>& requests,
                         const std::vector<std::size_t>& scene_of) {
  if (scene_of.size() != requests.size()) throw std::logic_error("simulateScenes: one scene index per request");
  for (std::size_t s : scene_of) {
    if (s >= scenes) throw std::logic_error("simulateScenes: a scene index out of range");
  }
}

}  // namespace

std::vector<SimulationResult> InProcessSimulationRunner::simulateScenes(const std::vector<const AcousticScene*>& scenes,
                                                                        const std::vector<SimulationRequest>& requests,
                                                                        const std::vector<std::size_t>& scene_of,
                                                                        std::vector<double>* wall_times_s) {
  requireSceneIndices(scenes.size(), requests, scene_of);
  std::vector<SimulationResult> results(requests.size());
  std::vector<double> times(requests.size(), 0.0);
  // The round's thread share is not used: each request says how many threads it has.
  runInRounds(requests.size(), parallel_, [&](std::size_t i, int) {
    const auto start = std::chrono::steady_clock::now();
    const SimulationRequest& r = requests[i];
    results[i] = simulateRoom(*scenes[scene_of[i]], r.source_m, r.listener_m, r.settings);
    times[i] = secondsSince(start);
  });
  if (wall_times_s) *wall_times_s = std::move(times);
  return results;
}

std::vector<SimulationResult> RemoteSimulationRunner::simulateScenes(const std::vector<const AcousticScene*>& scenes,
                                                                     const std::vector<SimulationRequest>& requests,
                                                                     const std::vector<std::size_t>& scene_of,
                                                                     std::vector<double>* wall_times_s) {
  requireSceneIndices(scenes.size(), requests, scene_of);
  for (const SimulationRequest& r : requests) {
    if (r.settings.rays.threads <= 0) {
      throw std::logic_error("a request to another process needs a fixed thread count (roundThreads)");
    }
  }
  std::vector<std::vector<std::uint8_t>> scene_bytes;
  for (const AcousticScene* scene : scenes) scene_bytes.push_back(encodeScene(*scene));
  std::lock_guard<std::mutex> batch(batch_mutex_);
  const std::size_t n = requests.size();
  ++counts_.batches;
  counts_.jobs += n;
  counts_.largest_batch = std::max(counts_.largest_batch, n);
  std::vector<std::optional<SimulationResult>> results(n);
  std::vector<std::exception_ptr> failures(n);
  std::vector<double> times(n, 0.0);
  std::atomic<std::size_t> next{0};
  auto serve = [&](std::size_t slot) {
    for (std::size_t i = next++; i < n; i = next++) {
      const auto start = std::chrono::steady_clock::now();
      try {
        const Reply reply = runOn(slot, encodeJob(scene_bytes[scene_of[i]], requests[i]));
        if (reply.status == Reply::Status::kResult) {
          results[i] = decodeResult(reply.result.data(), reply.result.size());
        } else if (reply.status == Reply::Status::kInputError) {
          throw InputError(reply.message);
        } else {
          throw std::runtime_error(reply.message);
        }
      } catch (const InputError&) {
        failures[i] = std::current_exception();
      } catch (...) {
        // A slot that fails (its worker died, its node went away) takes no more jobs.
        failures[i] = std::current_exception();
        return;
      }
      times[i] = secondsSince(start);
    }
  };
  const std::size_t used = std::min(slots(), n);
  std::vector<std::thread> threads;
  for (std::size_t slot = 1; slot < used; ++slot) threads.emplace_back(serve, slot);
  if (used > 0) serve(0);
  for (std::thread& t : threads) t.join();
  for (std::size_t i = 0; i < n; ++i) {
    if (failures[i]) std::rethrow_exception(failures[i]);
    if (!results[i]) {
      throw WorkerFailure("simulation " + std::to_string(i) + " was not run: all of the " + description() + " failed");
    }
  }
  if (wall_times_s) *wall_times_s = std::move(times);
  std::vector<SimulationResult> out;
  out.reserve(n);
  for (std::optional<SimulationResult>& r : results) out.push_back(std::move(*r));
  return out;
}

RemoteSimulationRunner::Counts RemoteSimulationRunner::counts() const {
  std::lock_guard<std::mutex> lock(batch_mutex_);
  return counts_;
}

struct WorkerProcessSimulationRunner::Workers {
  std::vector<std::unique_ptr<WorkerProcess>> processes;
};

WorkerProcessSimulationRunner::WorkerProcessSimulationRunner(std::vector<std::string> commands)
    : commands_(std::move(commands)), workers_(std::make_unique<Workers>()) {
  if (commands_.empty()) throw InputError("simulation workers: no worker command given");
  workers_->processes.resize(commands_.size());
}

WorkerProcessSimulationRunner::~WorkerProcessSimulationRunner() = default;

std::string WorkerProcessSimulationRunner::description() const {
  return std::to_string(commands_.size()) + " worker process" + (commands_.size() == 1 ? "" : "es");
}

RemoteSimulationRunner::Reply WorkerProcessSimulationRunner::runOn(std::size_t slot, const std::vector<std::uint8_t>& job) {
  std::unique_ptr<WorkerProcess>& process = workers_->processes[slot];
  if (!process) process = std::make_unique<WorkerProcess>(commands_[slot]);
  Frame frame = process->exchange(kJobFrame, job);
  Reply reply;
  if (frame.kind == kResultFrame) {
    reply.status = Reply::Status::kResult;
    reply.result = std::move(frame.payload);
  } else {
    reply.status = frame.kind == kInputErrorFrame ? Reply::Status::kInputError : Reply::Status::kFailure;
    reply.message.assign(frame.payload.begin(), frame.payload.end());
    if (frame.kind != kInputErrorFrame && frame.kind != kFailureFrame) {
      throw WorkerFailure("worker '" + commands_[slot] + "' answered with an unknown frame kind");
    }
    // A worker's own failure (not its job's) is the worker's: the runner stops using it.
    if (frame.kind == kFailureFrame) throw WorkerFailure("worker '" + commands_[slot] + "': " + reply.message);
  }
  return reply;
}

std::vector<std::uint8_t> SimulationJobExecutor::run(const std::uint8_t* job, std::size_t size) {
  const JobParts parts = splitJob(job, size);
  const bool same_scene = scene_ && scene_bytes_.size() == parts.scene_size &&
                          std::memcmp(scene_bytes_.data(), parts.scene, parts.scene_size) == 0;
  if (!same_scene) {
    scene_.reset();
    scene_ = decodeScene(parts.scene, parts.scene_size);
    scene_bytes_.assign(parts.scene, parts.scene + parts.scene_size);
  }
  const SimulationRequest& r = parts.request;
  return encodeResult(simulateRoom(*scene_, r.source_m, r.listener_m, r.settings));
}

std::vector<std::string> localWorkerCommands(int count, const std::string& tool_path) {
  return std::vector<std::string>(static_cast<std::size_t>(std::max(count, 0)), shellQuoted(tool_path) + " simulate-worker");
}

int serveSimulationJobs(int in_fd, int out_fd) {
  SimulationJobExecutor executor;
  for (;;) {
    std::optional<Frame> frame;
    try {
      frame = readFrame(in_fd);
    } catch (const std::runtime_error&) {
      return 2;
    }
    if (!frame) return 0;
    std::uint8_t kind = kResultFrame;
    std::vector<std::uint8_t> reply;
    auto message = [](const std::string& text) { return std::vector<std::uint8_t>(text.begin(), text.end()); };
    if (frame->kind != kJobFrame) {
      kind = kFailureFrame;
      reply = message("simulation worker: a frame of unknown kind " + std::to_string(frame->kind));
    } else {
      try {
        reply = executor.run(frame->payload.data(), frame->payload.size());
      } catch (const InputError& e) {
        kind = kInputErrorFrame;
        reply = message(e.what());
      } catch (const std::exception& e) {
        kind = kFailureFrame;
        reply = message(printableLine(std::string("simulation worker: ") + e.what()));
      }
    }
    if (!writeFrame(out_fd, kind, reply)) return 0;  // the caller has gone
  }
}

}  // namespace room_reverb::core
