// The head-tracked streaming renderer: equal to the offline render, a room swap without a
// click or a gap, head turns that move the source, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/convolution.h"
#include "room_reverb/binaural/binaural_cues.h"
#include "room_reverb/binaural/binaural_stream.h"
#include "room_reverb/binaural/reflection_tap_bank.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/reflection_tap.h"
#include "spherical_head.h"
#include "synthetic_rir.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;

const BinauralDecoder& decoder() { return room_reverb::test::sphericalHeadDecoder(3); }

// A third-order room: a plane wave from `direction` after 5 ms, then a decaying diffuse tail.
AudioBuffer room(const Eigen::Vector3d& direction, std::uint32_t seed, double duration_s = 0.3) {
  const auto frames = static_cast<std::size_t>(duration_s * 48000.0);
  AudioBuffer r = makeSilentBuffer(16, frames, 48000.0);
  const std::vector<double> y = sn3dHarmonics(3, direction);
  for (std::size_t c = 0; c < 16; ++c) {
    r.channels[c][240] = static_cast<float>(y[c]);
    const auto tail = room_reverb::test::exponentialDecayNoise(frames, 0.25, 480, seed + static_cast<std::uint32_t>(c));
    for (std::size_t n = 0; n < frames; ++n) r.channels[c][n] += 0.02f * tail[n];
  }
  return r;
}

Eigen::Vector3d unit(double azimuth_deg) {
  return {std::cos(azimuth_deg * kPi / 180.0), std::sin(azimuth_deg * kPi / 180.0), 0.0};
}

// Streams `source` (whole blocks) and returns left, right.
std::pair<std::vector<float>, std::vector<float>> stream(BinauralStream& s, const std::vector<float>& source) {
  const std::size_t b = s.blockSize();
  std::vector<float> left(source.size()), right(source.size());
  for (std::size_t at = 0; at + b <= source.size(); at += b) s.process(source.data() + at, left.data() + at, right.data() + at);
  return {left, right};
}

}  // namespace

TEST(BinauralStream, EqualsTheOfflineRenderWithNoAddedDelay) {
  const AudioBuffer r = room(unit(60.0), 3);
  const std::vector<float> source = room_reverb::test::whiteNoise(256 * 40, 9);
  BinauralStream s(decoder());
  s.setRoom(r);
  const auto [left, right] = stream(s, source);
  // Offline: the source through each channel of the room, then the decoder.
  AudioBuffer field = makeSilentBuffer(16, source.size() + r.frameCount() - 1, 48000.0);
  for (std::size_t c = 0; c < 16; ++c) field.channels[c] = fftConvolve(source, r.channels[c]);
  const AudioBuffer offline = decodeToBinaural(field, decoder());
  double error = 0.0, energy = 0.0;
  for (std::size_t n = 0; n < source.size(); ++n) {
    error += std::pow(left[n] - offline.channels[0][n], 2) + std::pow(right[n] - offline.channels[1][n], 2);
    energy += std::pow(offline.channels[0][n], 2) + std::pow(offline.channels[1][n], 2);
  }
  EXPECT_LT(10.0 * std::log10(error / energy), -100.0);
}

TEST(BinauralStream, RoomSwapHasNoClickAndNoGap) {
  std::vector<float> source(256 * 60);
  for (std::size_t n = 0; n < source.size(); ++n) source[n] = static_cast<float>(0.5 * std::sin(2.0 * kPi * 440.0 * n / 48000.0));
  BinauralStream s(decoder());
  s.setRoom(room(unit(90.0), 1));
  std::vector<float> left(source.size()), right(source.size());
  float largest_step_before = 0.0f;
  for (std::size_t block = 0; block < 60; ++block) {
    if (block == 30) s.setRoom(room(unit(-90.0), 2));
    const std::size_t at = block * 256;
    s.process(source.data() + at, left.data() + at, right.data() + at);
  }
  for (std::size_t n = 20 * 256 + 1; n < 30 * 256; ++n) {
    largest_step_before = std::max(largest_step_before, std::abs(left[n] - left[n - 1]));
  }
  float largest_step_swap = 0.0f, smallest_block_rms = 1e9f;
  for (std::size_t n = 30 * 256; n < 36 * 256; ++n) largest_step_swap = std::max(largest_step_swap, std::abs(left[n] - left[n - 1]));
  for (std::size_t block = 28; block < 40; ++block) {
    double e = 0.0;
    for (std::size_t n = block * 256; n < (block + 1) * 256; ++n) e += left[n] * left[n] + right[n] * right[n];
    smallest_block_rms = std::min(smallest_block_rms, static_cast<float>(std::sqrt(e / 512.0)));
  }
  // No step during the fade exceeds the signal's own largest step (the criterion),
  // no block falls silent, and the new room has the source on the right.
  EXPECT_LE(largest_step_swap, largest_step_before);  // measured: 0.98 of it
  EXPECT_GT(smallest_block_rms, 0.02f);
  // 440 Hz: an interaural level difference of about 3 dB at the side, to either side.
  const auto ear_energies = [&](std::size_t from_block, std::size_t to_block) {
    double l = 0.0, r = 0.0;
    for (std::size_t n = from_block * 256; n < to_block * 256; ++n) {
      l += left[n] * left[n];
      r += right[n] * right[n];
    }
    return std::make_pair(l, r);
  };
  const auto [l_before, r_before] = ear_energies(20, 30);
  const auto [l_after, r_after] = ear_energies(50, 60);
  EXPECT_GT(l_before, 1.5 * r_before);
  EXPECT_GT(r_after, 1.5 * l_after);
}

TEST(BinauralStream, TurningTheHeadLeftBringsALeftSourceToTheFront) {
  const std::vector<float> source = room_reverb::test::whiteNoise(256 * 40, 4);
  AudioBuffer dry = makeSilentBuffer(16, 4800, 48000.0);  // an anechoic plane wave from +90 deg
  const std::vector<double> y = sn3dHarmonics(3, unit(90.0));
  for (std::size_t c = 0; c < 16; ++c) dry.channels[c][0] = static_cast<float>(y[c]);
  const auto ild_db = [&](const Eigen::Quaterniond& head) {
    BinauralStream s(decoder());
    s.setRoom(dry);
    s.setHeadOrientation(head);
    const auto [left, right] = stream(s, source);
    double l = 0.0, r = 0.0;
    for (std::size_t n = 2560; n < left.size(); ++n) {
      l += left[n] * left[n];
      r += right[n] * right[n];
    }
    return 10.0 * std::log10(l / r);
  };
  const double facing = ild_db(Eigen::Quaterniond::Identity());
  const double turned = ild_db(Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitZ())));
  EXPECT_GT(facing, 5.0);            // the source on the left
  EXPECT_NEAR(turned, 0.0, 1.0);     // now in front (the 1 dB)
}

TEST(BinauralStream, NonFiniteSourceSamplesAreZeroedAndCounted) {
  BinauralStream s(decoder());
  s.setRoom(room(unit(0.0), 5));
  std::vector<float> source(256, 0.1f), left(256), right(256);
  source[7] = std::nanf("");
  source[9] = INFINITY;
  s.process(source.data(), left.data(), right.data());
  EXPECT_EQ(s.nonFiniteSamples(), 2u);
  for (std::size_t n = 0; n < 256; ++n) EXPECT_TRUE(std::isfinite(left[n]) && std::isfinite(right[n]));
}

TEST(BinauralStream, LongResponsesAreTruncatedWithAWarning) {
  BinauralStreamOptions options;
  options.max_response_s = 0.1;
  BinauralStream s(decoder(), options);
  EXPECT_NE(s.setRoom(room(unit(0.0), 6, 0.3)).find("truncated"), std::string::npos);
  EXPECT_EQ(s.setRoom(room(unit(0.0), 6, 0.05)), "");
}

TEST(BinauralStream, BadInput) {
  BinauralStream s(decoder());
  AudioBuffer five = makeSilentBuffer(5, 480, 48000.0);
  five.channels[0][0] = 1.0f;
  expectInputError([&] { s.setRoom(five); }, {"5 channels"});
  AudioBuffer at44 = room(unit(0.0), 7, 0.05);
  at44.sample_rate_hz = 44100.0;
  expectInputError([&] { s.setRoom(at44); }, {"48000"});
  AudioBuffer nan = room(unit(0.0), 7, 0.05);
  nan.channels[3][10] = std::nanf("");
  expectInputError([&] { s.setRoom(nan); }, {"NaN"});
  expectInputError([&] { s.setHeadOrientation(Eigen::Quaterniond(0.0, 0.0, 0.0, 0.0)); }, {"quaternion"});
  expectInputError([&] { s.setHeadOrientation(Eigen::Quaterniond(NAN, 0.0, 0.0, 1.0)); }, {"quaternion"});
  BinauralStreamOptions zero;
  zero.block_size = 0;
  expectInputError([&] { BinauralStream bad(decoder(), zero); }, {"block_size"});
  zero = BinauralStreamOptions();
  zero.early_crossfade_blocks = 0;
  expectInputError([&] { BinauralStream bad(decoder(), zero); }, {"crossfades"});
  expectInputError([&] { s.setEarlyResponse(five); }, {"early response", "5 channels"});
  expectInputError([&] { s.setEarlyResponse(at44); }, {"early response", "48000"});
  expectInputError([&] { s.setEarlyResponse(nan); }, {"early response", "NaN"});
}

TEST(BinauralStream, AnEarlyResponseAddsToTheRoomsAndGoesWhenRemoved) {
  // The room split in two, its first 10 ms as the early response: the same stream as the
  // whole room; removing the early response fades it out, leaving the rest.
  const AudioBuffer whole = room(unit(30.0), 5);
  AudioBuffer early = whole, late = whole;
  for (std::size_t c = 0; c < 16; ++c) {
    early.channels[c].resize(480);
    std::fill(late.channels[c].begin(), late.channels[c].begin() + 480, 0.0f);
  }
  const std::vector<float> source = room_reverb::test::whiteNoise(256 * 40, 4);
  BinauralStream reference(decoder()), split(decoder()), late_only(decoder());
  reference.setRoom(whole);
  split.setRoom(late);
  split.setEarlyResponse(early);
  late_only.setRoom(late);
  const auto [l1, r1] = stream(reference, source);
  const auto [l2, r2] = stream(split, source);
  stream(late_only, source);  // the same history as the others
  double worst = 0.0, peak = 0.0;
  for (std::size_t n = 0; n < source.size(); ++n) {
    worst = std::max({worst, static_cast<double>(std::abs(l1[n] - l2[n])), static_cast<double>(std::abs(r1[n] - r2[n]))});
    peak = std::max(peak, static_cast<double>(std::abs(l1[n])));
  }
  EXPECT_LT(worst, 1e-5 * peak);
  // Removed: after the fade (2 blocks) and the early response's 10 ms, the late room alone.
  split.setEarlyResponse(AudioBuffer());
  const auto [l3, r3] = stream(split, source);
  const auto [l4, r4] = stream(late_only, source);
  worst = 0.0;
  for (std::size_t n = 256 * 4; n < source.size(); ++n) worst = std::max(worst, static_cast<double>(std::abs(l3[n] - l4[n])));
  EXPECT_LT(worst, 1e-5 * peak);
}

TEST(BinauralStream, EarlyTapsAddToTheRoomAsTheirResponseWould) {
  // A reflection from 40 degrees at 7 ms as a tap beside a room holding only the tail,
  // against the same reflection written into the room's response.
  EarlyReflection reflection;
  reflection.time_of_arrival_s = 336.0 / 48000.0;
  reflection.level = 0.7;
  reflection.azimuth_rad = 40.0 * kPi / 180.0;
  const ReflectionTap shaped = shapeReflectionTap(reflection, 1, 0.002, 0.02, "test");
  AudioBuffer tail = room(unit(0.0), 5);
  for (auto& channel : tail.channels) channel[240] = 0.0f;  // the tail alone
  AudioBuffer whole = tail;
  const std::vector<double> y = sn3dHarmonics(3, unit(40.0));
  for (std::size_t c = 0; c < 16; ++c) whole.channels[c][336] += static_cast<float>(shaped.gain * y[c]);

  const std::vector<float> source = room_reverb::test::whiteNoise(256 * 40, 4);
  BinauralStream with_taps(decoder());
  with_taps.setRoom(tail);
  ReflectionTapBankOptions options;
  options.order = 3;
  auto bank = std::make_unique<ReflectionTapBank>(std::vector<EarlyReflection>{reflection}, options);
  bank->setTargets({{reflection.time_of_arrival_s, reflection.level, unit(40.0)}});
  with_taps.setEarlyTaps(std::move(bank));
  BinauralStream in_room(decoder());
  in_room.setRoom(whole);
  const auto [left, right] = stream(with_taps, source);
  const auto [left_expected, right_expected] = stream(in_room, source);
  double error = 0.0, energy = 0.0;
  // From the second block: the taps fade in over the first.
  for (std::size_t n = 256; n < source.size(); ++n) {
    error += std::pow(left[n] - left_expected[n], 2) + std::pow(right[n] - right_expected[n], 2);
    energy += std::pow(left_expected[n], 2) + std::pow(right_expected[n], 2);
  }
  EXPECT_LT(10.0 * std::log10(error / energy), -80.0);

  ReflectionTapBankOptions first_order;
  first_order.order = 1;
  EXPECT_THROW(with_taps.setEarlyTaps(std::make_unique<ReflectionTapBank>(std::vector<EarlyReflection>{reflection}, first_order)),
               InputError);
}

TEST(BinauralStream, ResponsesPreparedOnAnotherThreadSwapInAsTheBuffersDo) {
  // A room and an early part prepared on a second thread while the stream plays, then
  // swapped in: the same samples as setRoom and setEarlyResponse of the buffers at that
  // block.
  const std::vector<float> source = room_reverb::test::whiteNoise(256 * 40, 12);
  const AudioBuffer first = room(unit(20.0), 13, 0.5), second = room(unit(-70.0), 14, 0.5);
  AudioBuffer early = room(unit(110.0), 15, 0.03);
  BinauralStream direct(decoder()), prepared(decoder());
  direct.setRoom(first);
  prepared.setRoom(first);
  const std::vector<float> head(source.begin(), source.begin() + 256 * 17), tail(source.begin() + 256 * 17, source.end());
  auto [want_left, want_right] = stream(direct, head);
  direct.setRoom(second);
  direct.setEarlyResponse(early);
  const auto [want_left_tail, want_right_tail] = stream(direct, tail);

  PreparedResponse room_ready, early_ready;
  std::thread worker([&] {
    room_ready = prepared.prepareRoom(second);
    early_ready = prepared.prepareEarlyResponse(early);
  });
  auto [left, right] = stream(prepared, head);
  worker.join();
  EXPECT_EQ(prepared.setRoom(room_ready), "");
  EXPECT_EQ(prepared.setEarlyResponse(early_ready), "");
  const auto [left_tail, right_tail] = stream(prepared, tail);
  left.insert(left.end(), left_tail.begin(), left_tail.end());
  right.insert(right.end(), right_tail.begin(), right_tail.end());
  want_left.insert(want_left.end(), want_left_tail.begin(), want_left_tail.end());
  want_right.insert(want_right.end(), want_right_tail.begin(), want_right_tail.end());
  EXPECT_EQ(left, want_left);
  EXPECT_EQ(right, want_right);
  // A response prepared for the early convolver is not a room (another partition plan),
  // nor one of a stream with other options; the stream keeps its room.
  expectInputError([&] { prepared.setRoom(early_ready); }, {"another partition plan"});
  BinauralStreamOptions shorter;
  shorter.max_response_s = 0.2;
  const BinauralStream other(decoder(), shorter);
  const PreparedResponse truncated = other.prepareRoom(first);
  EXPECT_NE(truncated.warning.find("truncated"), std::string::npos);
  expectInputError([&] { prepared.setRoom(truncated); }, {"another partition plan"});
  expectInputError([&] { prepared.setRoom(PreparedResponse()); }, {"no prepared filters"});
  expectInputError([&] { prepared.prepareRoom(AudioBuffer()); }, {"room response"});
}
