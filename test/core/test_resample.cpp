#include <gtest/gtest.h>

#include <cmath>

#include "room_reverb/audio/resample.h"
#include "room_reverb/common/error.h"

using namespace room_reverb::core;

namespace {

AudioBuffer sine(double frequency_hz, double rate_hz, std::size_t frames, std::size_t channels = 1) {
  AudioBuffer buffer = makeSilentBuffer(channels, frames, rate_hz);
  for (std::size_t c = 0; c < channels; ++c) {
    for (std::size_t n = 0; n < frames; ++n) {
      buffer.channels[c][n] = static_cast<float>(0.5 * std::sin(2 * M_PI * frequency_hz * n / rate_hz + c));
    }
  }
  return buffer;
}

}  // namespace

TEST(Resample, SineKeepsFrequencyPhaseAndAmplitude) {
  const AudioBuffer in = sine(1000.0, 44100.0, 44100, 2);
  const AudioBuffer out = resample(in, 48000.0);
  ASSERT_EQ(out.sample_rate_hz, 48000.0);
  ASSERT_EQ(out.frameCount(), 48000u);
  ASSERT_EQ(out.channelCount(), 2u);
  // Away from the edges the output is the same sine sampled at 48 kHz, time-aligned.
  const AudioBuffer expected = sine(1000.0, 48000.0, 48000, 2);
  double max_error = 0.0;
  for (std::size_t c = 0; c < 2; ++c) {
    for (std::size_t n = 2000; n < 46000; ++n) {
      max_error = std::max(max_error, std::abs(static_cast<double>(out.channels[c][n]) - expected.channels[c][n]));
    }
  }
  EXPECT_LT(max_error, 1e-3);
}

TEST(Resample, ImpulseStaysAtItsTime) {
  AudioBuffer in = makeSilentBuffer(1, 44100, 44100.0);
  in.channels[0][4410] = 1.0f;  // 100 ms
  const AudioBuffer out = resample(in, 48000.0);
  std::size_t peak = 0;
  for (std::size_t n = 0; n < out.frameCount(); ++n) {
    if (std::abs(out.channels[0][n]) > std::abs(out.channels[0][peak])) peak = n;
  }
  EXPECT_NEAR(static_cast<double>(peak), 4800.0, 1.0);
}

TEST(Resample, SameRateIsACopy) {
  const AudioBuffer in = sine(440.0, 48000.0, 1000);
  EXPECT_EQ(resample(in, 48000.0).channels, in.channels);
}

TEST(Resample, RejectsAbsurdTargetRate) {
  const AudioBuffer in = sine(440.0, 48000.0, 1000);
  EXPECT_THROW(resample(in, 0.0), InputError);
  EXPECT_THROW(resample(in, 1e9), InputError);
}
