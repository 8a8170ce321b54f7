// The streaming renderer's dry sources: a looped file, and a topic's chunks through a
// jitter buffer with a streaming resampler; underruns, overflow, NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "room_reverb/audio/resample.h"
#include "room_reverb/audio/stream_resampler.h"
#include "room_reverb/binaural/source_feed.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;

AudioBuffer ramp(std::size_t frames, double rate = 48000.0) {
  AudioBuffer b = makeSilentBuffer(1, frames, rate);
  for (std::size_t n = 0; n < frames; ++n) b.channels[0][n] = static_cast<float>(n + 1) / 1000.0f;
  return b;
}

AudioBuffer sine(double frequency_hz, std::size_t frames, double rate, std::size_t offset = 0) {
  AudioBuffer b = makeSilentBuffer(1, frames, rate);
  for (std::size_t n = 0; n < frames; ++n) {
    b.channels[0][n] = static_cast<float>(0.5 * std::sin(2.0 * kPi * frequency_hz * (n + offset) / rate));
  }
  return b;
}

}  // namespace

TEST(LoopedSource, WrapsFromTheEndToTheStartAndSkips) {
  LoopedSource source(ramp(5));
  std::vector<float> out(12);
  source.read(out.data(), out.size());
  const std::vector<float> want = {0.001f, 0.002f, 0.003f, 0.004f, 0.005f, 0.001f,
                                   0.002f, 0.003f, 0.004f, 0.005f, 0.001f, 0.002f};
  EXPECT_EQ(out, want);
  source.skip(4);  // position 2 + 4 = 6 -> 1
  source.read(out.data(), 1);
  EXPECT_FLOAT_EQ(out[0], 0.002f);
}

TEST(LoopedSource, MixesToMonoAndResamples) {
  AudioBuffer stereo = sine(1000.0, 44100, 44100.0);
  stereo.channels.push_back(stereo.channels[0]);
  LoopedSource source(stereo);
  EXPECT_EQ(source.length(), 48000u);
}

TEST(LoopedSource, BadInput) {
  expectInputError([] { LoopedSource s(makeSilentBuffer(1, 0, 48000.0)); }, {"looped source"});
  AudioBuffer nan = ramp(10);
  nan.channels[0][3] = std::numeric_limits<float>::quiet_NaN();
  expectInputError([&] { LoopedSource s(nan); }, {"looped source"});
}

TEST(SourceQueue, PrebuffersThenPlaysInOrderAndCountsUnderruns) {
  SourceQueue queue(0.001, 1.0);  // 48 samples of prebuffer
  std::vector<float> out(32);
  queue.push(ramp(40));
  queue.read(out.data(), out.size());  // 40 < 48 queued: still waiting, silence, no underrun
  EXPECT_FALSE(queue.playing());
  EXPECT_EQ(out, std::vector<float>(32, 0.0f));
  queue.push(ramp(40));
  queue.read(out.data(), out.size());
  EXPECT_TRUE(queue.playing());
  EXPECT_FLOAT_EQ(out[0], 0.001f);
  EXPECT_FLOAT_EQ(out[31], 0.032f);
  queue.read(out.data(), out.size());  // 33..40, then 1..24 of the second ramp
  EXPECT_FLOAT_EQ(out[7], 0.040f);
  EXPECT_FLOAT_EQ(out[8], 0.001f);
  queue.read(out.data(), out.size());  // 16 left: 16 samples of underrun
  EXPECT_FLOAT_EQ(out[15], 0.040f);
  EXPECT_FLOAT_EQ(out[16], 0.0f);
  EXPECT_EQ(queue.counters().underrun_samples, 16u);
  EXPECT_FALSE(queue.playing());  // waits for the prebuffer again
}

TEST(SourceQueue, DiscardsTheOldestBeyondTheMaximumAndZeroesNonFiniteSamples) {
  SourceQueue queue(0.0, 0.001);  // at most 48 samples
  AudioBuffer chunk = ramp(100);
  chunk.channels[0][99] = std::numeric_limits<float>::infinity();
  chunk.channels[0][98] = std::numeric_limits<float>::quiet_NaN();
  queue.push(chunk);
  EXPECT_EQ(queue.queuedSamples(), 48u);
  EXPECT_EQ(queue.counters().overflow_samples, 52u);
  EXPECT_EQ(queue.counters().non_finite_samples, 2u);
  std::vector<float> out(48);
  queue.read(out.data(), out.size());
  EXPECT_FLOAT_EQ(out[0], 0.053f);
  EXPECT_EQ(out[46], 0.0f);
  EXPECT_EQ(out[47], 0.0f);
}

TEST(SourceQueue, ChunksAt44kAreResampledWithoutClicksAtTheirBoundaries) {
  SourceQueue queue(0.0, 10.0);
  // One second of a 1 kHz sine at 44.1 kHz in chunks of 441 samples.
  std::string note;
  for (std::size_t k = 0; k < 100; ++k) {
    const std::string n = queue.push(sine(1000.0, 441, 44100.0, 441 * k));
    if (k == 0) note = n;
    else EXPECT_EQ(n, "");
  }
  EXPECT_NE(note.find("resampled"), std::string::npos) << note;
  EXPECT_EQ(queue.counters().resampled_chunks, 100u);
  std::vector<float> out(queue.queuedSamples());
  ASSERT_NEAR(static_cast<double>(out.size()), 48000.0, 100.0);
  queue.read(out.data(), out.size());
  // Past the converter's start-up, a clean 1 kHz sine at 48 kHz: fit its phase and check
  // the residual (a restart per chunk would leave glitches every 480 samples).
  double worst = 0.0;
  const std::size_t start = 2000;
  double best_phase = 0.0, best_error = 1e9;
  for (int p = 0; p < 4800; ++p) {
    const double phase = 2.0 * kPi * p / 4800.0;
    double e = 0.0;
    for (std::size_t n = start; n < start + 96; ++n) {
      const double d = out[n] - 0.5 * std::sin(2.0 * kPi * 1000.0 * n / 48000.0 + phase);
      e += d * d;
    }
    if (e < best_error) {
      best_error = e;
      best_phase = phase;
    }
  }
  for (std::size_t n = start; n < out.size() - 2000; ++n) {
    worst = std::max(worst, std::abs(out[n] - 0.5 * std::sin(2.0 * kPi * 1000.0 * n / 48000.0 + best_phase)));
  }
  EXPECT_LT(worst, 2e-3) << "largest deviation from a clean sine";
}

TEST(SourceQueue, BadInput) {
  expectInputError([] { SourceQueue q(1.0, 0.5); }, {"prebuffer_s"});
  SourceQueue queue(0.0, 1.0);
  expectInputError([&] { queue.push(AudioBuffer{}); }, {"no channels"});
  AudioBuffer slow = ramp(10, 100.0);
  expectInputError([&] { queue.push(slow); }, {"100 Hz"});
  AudioBuffer ragged = makeSilentBuffer(2, 10, 48000.0);
  ragged.channels[1].resize(5);
  expectInputError([&] { queue.push(ragged); }, {"different lengths"});
}

TEST(StreamResampler, ChunkedOutputEqualsOneLongCall) {
  const AudioBuffer signal = sine(440.0, 44100, 44100.0);
  StreamResampler whole(44100.0, 48000.0), chunked(44100.0, 48000.0);
  std::vector<float> a, b;
  whole.process(signal.channels[0].data(), signal.frameCount(), a);
  for (std::size_t at = 0; at < signal.frameCount(); at += 300) {
    chunked.process(signal.channels[0].data() + at, std::min<std::size_t>(300, signal.frameCount() - at), b);
  }
  const std::size_t n = std::min(a.size(), b.size());
  ASSERT_GT(n, 47000u);
  for (std::size_t i = 0; i < n; ++i) ASSERT_NEAR(a[i], b[i], 1e-6) << i;
  expectInputError([] { StreamResampler r(0.0, 48000.0); }, {"outside"});
}
