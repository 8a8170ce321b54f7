// The mixed-order room response (binaural/late_order.h): unchanged before full_order_s,
// orders above 1 gone after it, and the late part's spectrum at each ear kept by the
// diffuse-field equaliser; the stream with mixed_order_late plays exactly the reduced
// response.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <random>
#include <vector>

#include "room_reverb/audio/convolution.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/binaural/binaural_stream.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/binaural/late_order.h"
#include "room_reverb/common/error.h"
#include "spherical_head.h"
#include "test_files.h"

using namespace room_reverb::core;

namespace {

constexpr double kFs = 48000.0;

const BinauralDecoder& ku100() {
  static const BinauralDecoder decoder = makeBinauralDecoder(HrtfSet::loadSofa(HrtfSet::defaultSofaPath()), 3);
  return decoder;
}

// A diffuse third-order field decaying with T60 = 1 s: independent noise per ACN channel,
// channel c of order l carrying 1 / (2l + 1) of the power (SN3D).
AudioBuffer diffuseTail(double seconds, std::uint32_t seed) {
  const auto frames = static_cast<std::size_t>(seconds * kFs);
  AudioBuffer b = makeSilentBuffer(16, frames, kFs);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const double delta = 3.0 * std::log(10.0) / kFs;  // amplitude decay for T60 = 1 s
  for (std::size_t c = 0; c < 16; ++c) {
    const double l = std::floor(std::sqrt(static_cast<double>(c)));
    const double scale = 0.1 / std::sqrt(2.0 * l + 1.0);
    for (std::size_t n = 0; n < frames; ++n) b.channels[c][n] = static_cast<float>(scale * normal(rng) * std::exp(-delta * n));
  }
  return b;
}

// The ears' responses: each channel through the decoder's filters, summed.
std::vector<std::vector<float>> decode(const AudioBuffer& ambix, const BinauralDecoder& decoder) {
  std::vector<std::vector<float>> ears(2, std::vector<float>(ambix.frameCount(), 0.0f));
  for (std::size_t c = 0; c < ambix.channelCount(); ++c) {
    const std::vector<float> left = fftConvolve(ambix.channels[c], decoder.filters[c].left);
    const std::vector<float> right = fftConvolve(ambix.channels[c], decoder.filters[c].right);
    for (std::size_t n = 0; n < ears[0].size() && n < left.size(); ++n) {
      ears[0][n] += left[n];
      ears[1][n] += right[n];
    }
  }
  return ears;
}

struct OctaveStatistics {
  double left_db, right_db, coherence;
};

// Energy per ear and interaural coherence (|cross-spectrum| over the geometric mean of
// the auto-spectra, Welch-averaged over 1024-sample segments) in the octave about
// centre_hz, over the frames [from, to).
OctaveStatistics octave(const std::vector<std::vector<float>>& ears, std::size_t from, std::size_t to, double centre_hz) {
  constexpr std::size_t kSegment = 1024;
  RealFft fft(kSegment);
  std::vector<float> segment(kSegment);
  std::vector<std::complex<float>> l(fft.spectrumSize()), r(fft.spectrumSize());
  double ll = 0.0, rr = 0.0;
  std::complex<double> lr = 0.0;
  const auto windowed = [&](const std::vector<float>& ear, std::size_t start, std::complex<float>* spectrum) {
    for (std::size_t i = 0; i < kSegment; ++i) {
      const double w = 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / kSegment);
      segment[i] = static_cast<float>(w * ear[start + i]);
    }
    fft.forward(segment.data(), spectrum);
  };
  for (std::size_t start = from; start + kSegment <= to; start += kSegment / 2) {
    windowed(ears[0], start, l.data());
    windowed(ears[1], start, r.data());
    for (std::size_t k = 1; k < l.size(); ++k) {
      const double f = static_cast<double>(k) * kFs / kSegment;
      if (f < centre_hz / std::sqrt(2.0) || f >= centre_hz * std::sqrt(2.0)) continue;
      ll += std::norm(l[k]);
      rr += std::norm(r[k]);
      lr += std::complex<double>(l[k]) * std::conj(std::complex<double>(r[k]));
    }
  }
  return {10.0 * std::log10(ll), 10.0 * std::log10(rr), std::abs(lr) / std::sqrt(ll * rr)};
}

TEST(LateOrder, TheReducedResponseKeepsTheEarlyPartAndTheLateSpectrum) {
  const AudioBuffer full = diffuseTail(0.8, 3);
  const double keep_s = 0.1;
  const AudioBuffer mixed = reduceLateOrder(full, ku100(), keep_s);
  ASSERT_EQ(mixed.channelCount(), 16u);
  const auto fade_start = static_cast<std::size_t>(keep_s * kFs) - 128;
  // Unchanged before the fade (the equaliser reaches 127 samples back into it).
  for (std::size_t c = 0; c < 16; ++c) {
    for (std::size_t n = 0; n + 127 < fade_start; ++n) ASSERT_EQ(mixed.channels[c][n], full.channels[c][n]) << c << " " << n;
  }
  // Orders 2-3 end with the fade; orders 0-1 go on.
  for (std::size_t c = 4; c < 16; ++c) {
    EXPECT_NE(mixed.channels[c][fade_start + 100], 0.0f);
    for (std::size_t n = fade_start + 256; n < full.frameCount(); ++n) ASSERT_EQ(mixed.channels[c][n], 0.0f) << c << " " << n;
  }
  for (std::size_t c = 0; c < 4; ++c) EXPECT_NE(mixed.channels[c][full.frameCount() / 2], 0.0f);

  // At the ears, past the fade: the same energy per octave within 1 dB from 250 Hz to
  // 8 kHz (the equaliser's job); the coherence between the ears is what the truncation
  // changes, reported.
  const auto ears_full = decode(full, ku100());
  const auto ears_mixed = decode(mixed, ku100());
  const std::size_t from = static_cast<std::size_t>(0.15 * kFs), to = static_cast<std::size_t>(0.75 * kFs);
  for (double centre : {250.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0}) {
    const OctaveStatistics a = octave(ears_full, from, to, centre), b = octave(ears_mixed, from, to, centre);
    std::printf("%5.0f Hz: level %+.2f / %+.2f dB, coherence %.2f -> %.2f\n", centre, b.left_db - a.left_db,
                b.right_db - a.right_db, a.coherence, b.coherence);
    EXPECT_NEAR(b.left_db, a.left_db, 1.0) << centre << " Hz";
    EXPECT_NEAR(b.right_db, a.right_db, 1.0) << centre << " Hz";
  }
}

TEST(LateOrder, TheStreamPlaysTheReducedResponse) {
  const AudioBuffer room = diffuseTail(0.4, 5);
  BinauralStreamOptions options;
  options.mixed_order_late = true;
  options.full_order_s = 0.05;
  BinauralStream mixed(ku100(), options), reference(ku100());
  mixed.setRoom(room);
  reference.setRoom(reduceLateOrder(room, ku100(), 0.05));
  std::mt19937 rng(7);
  std::normal_distribution<float> normal;
  std::vector<float> block(mixed.blockSize()), l1(block.size()), r1(block.size()), l2(block.size()), r2(block.size());
  for (int b = 0; b < 120; ++b) {
    for (float& x : block) x = normal(rng);
    mixed.process(block.data(), l1.data(), r1.data());
    reference.process(block.data(), l2.data(), r2.data());
    ASSERT_EQ(l1, l2) << "block " << b;
    ASSERT_EQ(r1, r2) << "block " << b;
  }
}

// What an offline rendering of the stream's room takes (the node's ~render_to_file): the
// reduced response with mixed_order_late, the response itself without it or for a
// first-order room.
TEST(LateOrder, TheRoomAsStreamedIsTheReducedResponseWhenMixed) {
  const AudioBuffer room = diffuseTail(0.3, 11);
  BinauralStreamOptions options;
  options.full_order_s = 0.05;
  EXPECT_EQ(roomResponseAsStreamed(room, ku100(), options).channels, room.channels);
  options.mixed_order_late = true;
  EXPECT_EQ(roomResponseAsStreamed(room, ku100(), options).channels, reduceLateOrder(room, ku100(), 0.05).channels);
  AudioBuffer first = room;
  first.channels.resize(4);
  EXPECT_EQ(roomResponseAsStreamed(first, ku100(), options).channels, first.channels);
  options.full_order_s = -1.0;
  room_reverb::test::expectInputError([&] { roomResponseAsStreamed(room, ku100(), options); }, {"finite", ">= 0"});
}

TEST(LateOrder, FirstOrderRoomsAreUnchangedAndBadInputIsRefused) {
  AudioBuffer first = diffuseTail(0.3, 9);
  first.channels.resize(4);
  EXPECT_EQ(reduceLateOrder(first, ku100(), 0.05).channels, first.channels);
  const AudioBuffer room = diffuseTail(0.3, 9);
  room_reverb::test::expectInputError([&] { reduceLateOrder(room, ku100(), -0.1); }, {"finite", ">= 0"});
  room_reverb::test::expectInputError([&] { reduceLateOrder(room, ku100(), NAN); }, {"finite"});
  room_reverb::test::expectInputError([&] { reduceLateOrder(room, room_reverb::test::sphericalHeadDecoder(1), 0.05); },
                                      {"16 channels", "order 1"});
  room_reverb::test::expectInputError([&] { lateOrderEqualiser(room_reverb::test::sphericalHeadDecoder(1)); },
                                      {"order 2 or 3"});
  BinauralStreamOptions options;
  options.full_order_s = -1.0;
  room_reverb::test::expectInputError([&] { BinauralStream(ku100(), options); }, {"full_order_s"});
}

}  // namespace
