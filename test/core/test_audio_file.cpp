#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <unistd.h>

#include "test_files.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/common/error.h"
#include "synthetic_rir.h"

using namespace room_reverb::core;
namespace fs = std::filesystem;

namespace {

using room_reverb::test::expectInputError;
using room_reverb::test::tempPath;
using room_reverb::test::writeFile;

AudioBuffer rampBuffer(std::size_t channels, std::size_t frames, double rate) {
  AudioBuffer buffer = makeSilentBuffer(channels, frames, rate);
  for (std::size_t c = 0; c < channels; ++c) {
    for (std::size_t n = 0; n < frames; ++n) {
      buffer.channels[c][n] = 0.9f * std::sin(0.01f * (n + 1) * (c + 1));
    }
  }
  return buffer;
}

}  // namespace

struct EncodingCase {
  const char* extension;
  SampleEncoding encoding;
  double tolerance;
};

class AudioFileRoundTrip : public ::testing::TestWithParam<EncodingCase> {};

TEST_P(AudioFileRoundTrip, KeepsSamplesChannelsAndRate) {
  const EncodingCase c = GetParam();
  // FLAC holds at most 8 channels; WAV is checked up to 16 (third-order ambisonics).
  const bool flac = std::string(c.extension) == ".flac";
  for (std::size_t channels : {1u, 2u, 4u, flac ? 8u : 16u}) {
    const AudioBuffer original = rampBuffer(channels, 1000, 44100.0);
    const fs::path path = tempPath("roundtrip_" + std::to_string(channels) + c.extension);
    writeAudioFile(path.string(), original, c.encoding);
    const AudioBuffer read = readAudioFile(path.string());
    ASSERT_EQ(read.channelCount(), channels);
    ASSERT_EQ(read.frameCount(), 1000u);
    EXPECT_EQ(read.sample_rate_hz, 44100.0);
    double max_error = 0.0;
    for (std::size_t ch = 0; ch < channels; ++ch) {
      for (std::size_t n = 0; n < 1000; ++n) {
        max_error = std::max(max_error, std::abs(static_cast<double>(read.channels[ch][n]) - original.channels[ch][n]));
      }
    }
    EXPECT_LT(max_error, c.tolerance) << channels << " channels";
  }
}

INSTANTIATE_TEST_SUITE_P(Encodings, AudioFileRoundTrip,
                         ::testing::Values(EncodingCase{".wav", SampleEncoding::kPcm16, 1.0 / 32768 + 1e-6},
                                           EncodingCase{".wav", SampleEncoding::kPcm24, 1.0 / 8388608 + 1e-7},
                                           EncodingCase{".wav", SampleEncoding::kPcm32, 1e-7},
                                           EncodingCase{".wav", SampleEncoding::kFloat32, 1e-9},
                                           EncodingCase{".flac", SampleEncoding::kPcm16, 1.0 / 32768 + 1e-6},
                                           EncodingCase{".flac", SampleEncoding::kPcm24, 1.0 / 8388608 + 1e-7}));

TEST(AudioFile, MissingFileIsAClearError) {
  expectInputError([] { readAudioFile("/nonexistent/dir/rir.wav"); }, {"no such file"});
}

TEST(AudioFile, TextFileIsNotAudio) {
  const fs::path path = tempPath("not_audio.wav");
  std::ofstream(path) << "this is not a wav file\n";
  expectInputError([&] { readAudioFile(path.string()); }, {"not a readable audio file"});
}

TEST(AudioFile, DirectoryIsNotAudio) {
  expectInputError([] { readAudioFile(fs::temp_directory_path().string()); }, {"directory"});
}

TEST(AudioFile, EmptyFileIsAClearError) {
  const fs::path path = tempPath("empty.wav");
  std::ofstream(path).close();
  EXPECT_THROW(readAudioFile(path.string()), InputError);
}

TEST(AudioFile, WavWithNoSamplesIsAClearError) {
  // A valid header with a zero-length data chunk, written by hand.
  const fs::path path = tempPath("no_samples.wav");
  const unsigned char header[44] = {'R', 'I', 'F', 'F', 36, 0, 0, 0, 'W', 'A', 'V', 'E', 'f', 'm', 't', ' ',
                                    16, 0, 0, 0, 1, 0, 1, 0, 0x80, 0xBB, 0, 0, 0, 0x77, 1, 0, 2, 0, 16, 0,
                                    'd', 'a', 't', 'a', 0, 0, 0, 0};
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(header), sizeof(header));
  expectInputError([&] { readAudioFile(path.string()); }, {"no_samples.wav"});
}

TEST(AudioFile, NanSamplesAreRejectedOnRead) {
  AudioBuffer buffer = rampBuffer(1, 100, 48000.0);
  const fs::path path = tempPath("nan.wav");
  writeAudioFile(path.string(), buffer, SampleEncoding::kFloat32);
  // Patch a NaN into the float data (the last sample) directly in the file.
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(-4, std::ios::end);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    file.write(reinterpret_cast<const char*>(&nan), sizeof(nan));
  }
  expectInputError([&] { readAudioFile(path.string()); }, {"NaN"});
}

TEST(AudioFile, WritingNonFiniteSamplesIsRefused) {
  AudioBuffer buffer = rampBuffer(1, 100, 48000.0);
  buffer.channels[0][10] = std::numeric_limits<float>::infinity();
  expectInputError([&] { writeAudioFile(tempPath("inf.wav").string(), buffer); }, {"infinite"});
}

TEST(AudioFile, UnknownExtensionAndFloatFlacAreRefused) {
  const AudioBuffer buffer = rampBuffer(1, 100, 48000.0);
  expectInputError([&] { writeAudioFile(tempPath("x.mp3").string(), buffer); }, {"extension"});
  expectInputError([&] { writeAudioFile(tempPath("x.flac").string(), buffer, SampleEncoding::kFloat32); }, {"FLAC"});
}

TEST(AudioFile, AbsurdSampleRatesAreRejected) {
  for (double rate : {0.0, 100.0, 5e6}) {
    AudioBuffer buffer = rampBuffer(1, 100, 48000.0);
    buffer.sample_rate_hz = rate;
    expectInputError([&] { validateAudioBuffer(buffer, "buffer"); }, {"sample rate"});
  }
}

TEST(AudioFile, ZeroHzWavHeaderIsAClearError) {
  // Header claiming 0 Hz followed by a few samples.
  const fs::path path = tempPath("zero_rate.wav");
  unsigned char header[52] = {'R', 'I', 'F', 'F', 44, 0, 0, 0, 'W', 'A', 'V', 'E', 'f', 'm', 't', ' ',
                              16, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 16, 0,
                              'd', 'a', 't', 'a', 8, 0, 0, 0, 1, 0, 2, 0, 3, 0, 4, 0};
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(header), sizeof(header));
  EXPECT_THROW(readAudioFile(path.string()), InputError);
}

TEST(AudioBuffer, InterleaveRoundTrip) {
  const AudioBuffer buffer = rampBuffer(3, 17, 48000.0);
  const AudioBuffer back = deinterleave(interleave(buffer), 3, 48000.0);
  EXPECT_EQ(back.channels, buffer.channels);
  EXPECT_THROW(deinterleave(std::vector<float>(10), 3, 48000.0), InputError);
  EXPECT_THROW(deinterleave(std::vector<float>(10), 0, 48000.0), InputError);
}
