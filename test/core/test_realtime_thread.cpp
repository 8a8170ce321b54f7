#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <thread>

#include "room_reverb/common/error.h"
#include "room_reverb/common/realtime_thread.h"

namespace room_reverb::core {
namespace {

struct Observed {
  ThreadScheduling reported;
  int policy = -1;
  int priority = -1;
};

// Each request runs on a thread of its own, so the test binary keeps normal scheduling.
Observed requestOnNewThread(int priority) {
  Observed observed;
  std::thread([&] {
    observed.reported = requestRealtimeScheduling(priority);
    sched_param parameters{};
    pthread_getschedparam(pthread_self(), &observed.policy, &parameters);
    observed.priority = parameters.sched_priority;
  }).join();
  return observed;
}

TEST(RealtimeThread, TheReportedClassIsTheOneTheKernelGives) {
  // Granted or refused depends on the machine (root or rtprio in a container with
  // CAP_SYS_NICE, or not); either way the report must match what the kernel says.
  const Observed observed = requestOnNewThread(10);
  if (observed.reported.realtime) {
    EXPECT_EQ(observed.policy, SCHED_FIFO);
    EXPECT_EQ(observed.priority, 10);
    EXPECT_EQ(observed.reported.description, "SCHED_FIFO 10");
  } else {
    EXPECT_EQ(observed.policy, SCHED_OTHER);
    EXPECT_NE(observed.reported.description.find("SCHED_FIFO 10 refused"), std::string::npos)
        << observed.reported.description;
  }
}

TEST(RealtimeThread, PriorityZeroKeepsNormalScheduling) {
  const Observed observed = requestOnNewThread(0);
  EXPECT_FALSE(observed.reported.realtime);
  EXPECT_EQ(observed.policy, SCHED_OTHER);
  EXPECT_EQ(observed.reported.description, "normal (real-time priority 0)");
}

TEST(RealtimeThread, PrioritiesOutsideTheKernelsRangeAreRefusedInOneLine) {
  for (const int priority : {-1, 100, 1000}) {
    try {
      requestRealtimeScheduling(priority);
      ADD_FAILURE() << priority << " accepted";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("outside 0-99"), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace room_reverb::core
