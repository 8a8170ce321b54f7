#include "room_reverb/common/parallel_rows.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace room_reverb::core {

void forEachRow(int rows, int threads, const std::function<void(int)>& body) {
  int count = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  count = std::clamp(count, 1, std::max(rows, 1));
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&] {
    for (int row = next++; row < rows; row = next++) {
      try {
        body(row);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = rows;  // stop handing out rows
      }
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < count; ++i) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace room_reverb::core
