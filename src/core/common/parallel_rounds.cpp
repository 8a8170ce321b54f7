#include "room_reverb/common/parallel_rounds.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace room_reverb::core {
namespace {

std::size_t workerCount(int threads) {
  return static_cast<std::size_t>(threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace

int roundThreads(std::size_t count, int threads, std::size_t i) {
  const std::size_t workers = workerCount(threads);
  const std::size_t first = i / workers * workers;
  const std::size_t in_round = std::min(workers, count - first);
  return static_cast<int>(std::max<std::size_t>(1, workers / in_round));
}

void runInRounds(std::size_t count, int threads, const std::function<void(std::size_t, int)>& job) {
  const std::size_t workers = std::min(workerCount(threads), count);
  std::vector<std::exception_ptr> failures(count);
  // Each worker takes the next job as soon as it is free (jobs differ in length, and a
  // worker waiting for a round's slowest job idles); which threads a job gets still
  // depends only on its index.
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        job(i, roundThreads(count, threads, i));
      } catch (...) {
        failures[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
}

}  // namespace room_reverb::core
