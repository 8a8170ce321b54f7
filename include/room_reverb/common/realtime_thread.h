#pragma once
// Real-time scheduling for an audio thread. A thread at normal priority shares the cores
// with every compiler and tracer on the machine: in an hour's soak on 2 busy cores (load
// 4-10) the binaural renderer's worst chunk took 203 ms and 3262 chunks were dropped
// (docs/reliability.md). Audio software asks the kernel for a fixed-priority class
// (SCHED_FIFO), as JACK does for its clients; a thread that paces itself by sleeping
// between chunks cannot starve the machine with it.
#include <string>

namespace room_reverb::core {

struct ThreadScheduling {
  bool realtime = false;    // the thread runs under SCHED_FIFO
  std::string description;  // "SCHED_FIFO 10", or "normal (SCHED_FIFO 10 refused: ...)"
};

// Asks for SCHED_FIFO at `priority` (1-99) for the calling thread; 0 keeps the normal
// class. Refusal (no CAP_SYS_NICE and no RLIMIT_RTPRIO, e.g. a user outside the `audio`
// group) is not an error: the thread keeps its class and the description says why.
// Throws InputError for a priority outside 0-99.
ThreadScheduling requestRealtimeScheduling(int priority);

}  // namespace room_reverb::core
