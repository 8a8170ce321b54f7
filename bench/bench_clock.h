#pragma once
// The calling thread's processor time, for benchmarks that report real-time shares: time
// the thread spends preempted by other processes does not count.
#include <time.h>

namespace room_reverb::bench {

inline double threadCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace room_reverb::bench
