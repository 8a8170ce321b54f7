#include "room_reverb/common/realtime_thread.h"

#include <pthread.h>
#include <sched.h>

#include <cstring>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

ThreadScheduling requestRealtimeScheduling(int priority) {
  if (priority < 0 || priority > 99) {
    throw InputError("real-time priority " + std::to_string(priority) +
                     " is outside 0-99 (0 keeps normal scheduling; JACK's default is 10)");
  }
  ThreadScheduling result;
  if (priority == 0) {
    result.description = "normal (real-time priority 0)";
    return result;
  }
  sched_param parameters{};
  parameters.sched_priority = priority;
  const int status = pthread_setschedparam(pthread_self(), SCHED_FIFO, &parameters);
  const std::string asked = "SCHED_FIFO " + std::to_string(priority);
  if (status != 0) {
    result.description = "normal (" + asked + " refused: " + std::strerror(status) +
                         "; grant rtprio, e.g. membership of the audio group)";
    return result;
  }
  result.realtime = true;
  result.description = asked;
  return result;
}

}  // namespace room_reverb::core
