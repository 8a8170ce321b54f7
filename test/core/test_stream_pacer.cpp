// The streaming renderer's clock bookkeeping: on-time chunks, late ones, dropped ones when
// far behind, a clock that jumps back, a simulated clock not yet running.
#include <gtest/gtest.h>

#include "room_reverb/binaural/stream_pacer.h"
#include "test_files.h"

using namespace room_reverb::core;

namespace {

StreamPacerOptions options() {
  StreamPacerOptions o;
  o.chunk_period_s = 0.01;
  o.late_tolerance_s = 0.01;
  o.max_lag_s = 0.1;
  return o;
}

}  // namespace

TEST(StreamPacer, WaitsForEachChunksTimeAndCountsNothingWhenOnTime) {
  StreamPacer pacer(options());
  double now = 100.0;
  for (int k = 0; k < 50; ++k) {
    auto step = pacer.next(now);
    if (k > 0) {
      // Asked before the chunk is due: wait until exactly its time.
      EXPECT_EQ(step.kind, StreamPacer::Step::kWait);
      EXPECT_NEAR(step.until, 100.0 + 0.01 * k, 1e-12);
      now = step.until;
      step = pacer.next(now);
    }
    ASSERT_EQ(step.kind, StreamPacer::Step::kRender);
    EXPECT_EQ(step.dropped, 0u);
    EXPECT_EQ(pacer.chunkIndex(), static_cast<std::uint64_t>(k));
    pacer.published(now + 0.002);  // 2 ms to render and publish
    now += 0.004;
  }
  EXPECT_EQ(pacer.counters().published, 50u);
  EXPECT_EQ(pacer.counters().late, 0u);
  EXPECT_EQ(pacer.counters().dropped, 0u);
  EXPECT_DOUBLE_EQ(pacer.startTime(), 100.0);
}

TEST(StreamPacer, ChunksPublishedBeyondTheToleranceAreLateAndCatchUpWithoutDrops) {
  StreamPacer pacer(options());
  ASSERT_EQ(pacer.next(10.0).kind, StreamPacer::Step::kRender);
  pacer.published(10.0);
  // A 35 ms stall (a room swap): chunks 1..3 are overdue; rendered back to back.
  double now = 10.045;
  for (int k = 1; k <= 4; ++k) {
    const auto step = pacer.next(now);
    ASSERT_EQ(step.kind, StreamPacer::Step::kRender);
    EXPECT_EQ(step.dropped, 0u);
    pacer.published(now);
    now += 0.001;
  }
  // Chunk 1 was due at 10.01 (35 ms late), 2 at 10.02, 3 at 10.03 (16 ms late): late;
  // chunk 4, due at 10.04 and published at 10.048: within the tolerance.
  EXPECT_EQ(pacer.counters().late, 3u);
  EXPECT_EQ(pacer.counters().dropped, 0u);
  EXPECT_EQ(pacer.next(now).kind, StreamPacer::Step::kWait);
}

TEST(StreamPacer, FarBehindItDropsThePastChunksAndResumesWithTheCurrentOne) {
  StreamPacer pacer(options());
  pacer.next(0.5);
  pacer.published(0.5);
  const auto step = pacer.next(0.5 + 0.255);  // 255 ms later: chunks 1..24 have passed
  ASSERT_EQ(step.kind, StreamPacer::Step::kRender);
  EXPECT_EQ(step.dropped, 24u);
  EXPECT_EQ(pacer.chunkIndex(), 25u);
  EXPECT_EQ(pacer.counters().dropped, 24u);
  pacer.published(0.5 + 0.256);
  EXPECT_EQ(pacer.counters().late, 0u);  // chunk 25 went out in time
}

TEST(StreamPacer, AClockThatJumpsBackRestartsTheTimeline) {
  StreamPacer pacer(options());
  for (double t = 50.0; t < 50.1; t += 0.01) {
    if (pacer.next(t).kind == StreamPacer::Step::kRender) pacer.published(t);
  }
  ASSERT_GT(pacer.chunkIndex(), 5u);
  const auto step = pacer.next(20.0);  // a bag replayed from its start
  EXPECT_EQ(step.kind, StreamPacer::Step::kRender);
  EXPECT_EQ(pacer.chunkIndex(), 0u);
  EXPECT_DOUBLE_EQ(pacer.startTime(), 20.0);
  EXPECT_EQ(pacer.counters().restarts, 1u);
  EXPECT_EQ(pacer.counters().dropped, 0u);
}

TEST(StreamPacer, ASimulatedClockAtZeroIsWaitedOut) {
  StreamPacer pacer(options());
  EXPECT_EQ(pacer.next(0.0).kind, StreamPacer::Step::kWait);
  EXPECT_FALSE(pacer.started());
  EXPECT_EQ(pacer.next(3.0).kind, StreamPacer::Step::kRender);
  EXPECT_DOUBLE_EQ(pacer.startTime(), 3.0);
}

TEST(StreamPacer, BadOptions) {
  StreamPacerOptions o = options();
  o.chunk_period_s = 0.0;
  room_reverb::test::expectInputError([&] { StreamPacer p(o); }, {"chunk_period_s"});
  o = options();
  o.max_lag_s = 0.001;  // below the late tolerance
  room_reverb::test::expectInputError([&] { StreamPacer p(o); }, {"max_lag_s"});
}
