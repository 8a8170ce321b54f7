#pragma once
// Independent jobs (the measured pairs of a comparison, a batch of simulations) run in
// rounds on a fixed number of threads, each job told how many threads it may use itself.
#include <cstddef>
#include <functional>

namespace room_reverb::core {

// The thread count job i of `count` gets from runInRounds with `threads` (0: all
// hardware threads): one each in a full round; the jobs of a last, smaller round share the
// threads. It depends only on i, count and threads, so results that depend on a job's
// thread count (the ray tracer's sums) are reproducible, wherever the job runs.
int roundThreads(std::size_t count, int threads, std::size_t i);

// Calls job(i, roundThreads(count, threads, i)) for every i in [0, count): up to `threads`
// jobs at once, each worker starting the next job when its last one ends (the tracer
// parallelises within a simulation, the analysis of a response does not). The first exception (lowest i) of a job is rethrown after every job
// has ended.
void runInRounds(std::size_t count, int threads, const std::function<void(std::size_t, int)>& job);

}  // namespace room_reverb::core
