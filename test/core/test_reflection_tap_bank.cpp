// The early reflections as moving delay-line taps (binaural/reflection_tap_bank.h): at rest
// they are the RSAO's resynthesised early part; moving, their output stays as smooth as
// the source itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/binaural/reflection_tap_bank.h"
#include "room_reverb/common/error.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/rsao/lpc.h"
#include "room_reverb/rsao/reflection_tap.h"
#include "room_reverb/rsao/rsao_estimator.h"
#include "room_reverb/rsao/rsao_resynthesis.h"

using namespace room_reverb::core;

namespace {

constexpr double kFs = 48000.0;
constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kBlock = 256;

// A measured RSAO (Terry's typing room) with its arrivals moved to whole samples, where
// both the resynthesis' windowed sinc and the taps' cubic interpolation are exact.
Rsao measuredRsaoOnWholeSamples() {
  const AudioBuffer rir = readAudioFile(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/rirs/bformat/terrys_typing_room.wav");
  Rsao rsao = estimateRsao(rir, AmbisonicFormat::kFuMa);
  for (EarlyReflection& r : rsao.reflections) r.time_of_arrival_s = std::round(r.time_of_arrival_s * kFs) / kFs;
  return rsao;
}

std::vector<TapTarget> targetsOf(const std::vector<EarlyReflection>& reflections) {
  std::vector<TapTarget> targets;
  for (const EarlyReflection& r : reflections) targets.push_back({r.time_of_arrival_s, r.level, reflectionDirection(r)});
  return targets;
}

// A bank of one tap with no spectral shape, of `level`, at the tests' block size.
ReflectionTapBank unshapedTap(double level) {
  EarlyReflection r;
  r.level = level;
  ReflectionTapBankOptions options;
  options.block_size = kBlock;
  return ReflectionTapBank({r}, options);
}

// Runs `blocks` blocks of `source` (padded with zeros) through the bank; the field's
// channels, concatenated.
std::vector<std::vector<float>> run(ReflectionTapBank& bank, const std::vector<float>& source, std::size_t blocks,
                                    const std::function<void(std::size_t)>& before_block = {}) {
  std::vector<std::vector<float>> field(bank.channels(), std::vector<float>(blocks * kBlock, 0.0f));
  std::vector<float> block(kBlock);
  std::vector<float*> out(bank.channels());
  for (std::size_t b = 0; b < blocks; ++b) {
    if (before_block) before_block(b);
    for (std::size_t n = 0; n < kBlock; ++n) {
      const std::size_t i = b * kBlock + n;
      block[n] = i < source.size() ? source[i] : 0.0f;
    }
    for (std::size_t c = 0; c < bank.channels(); ++c) out[c] = field[c].data() + b * kBlock;
    bank.process(block.data(), out.data());
  }
  return field;
}

TEST(ReflectionTapBank, AtRestTheTapsAreTheResynthesisedEarlyPart) {
  const Rsao rsao = measuredRsaoOnWholeSamples();
  ReflectionTapBankOptions options;
  options.order = 1;
  options.block_size = kBlock;
  ReflectionTapBank bank(rsao.reflections, options);
  bank.setTargets(targetsOf(rsao.reflections));
  const std::size_t blocks = static_cast<std::size_t>(std::ceil((rsao.late.mixing_time_s + 0.03) * kFs / kBlock));
  const auto field = run(bank, {1.0f}, blocks);

  ResynthesisOptions early_only;
  early_only.include_late = false;
  early_only.duration_s = static_cast<double>(blocks * kBlock) / kFs;
  const AudioBuffer expected = resynthesizeRsao(rsao, early_only);
  double peak = 0.0, worst = 0.0, energy = 0.0, error = 0.0;
  for (std::size_t c = 0; c < 4; ++c) {
    for (std::size_t n = 0; n < field[c].size(); ++n) {
      const double e = expected.channels[c][n];
      peak = std::max(peak, std::abs(e));
      worst = std::max(worst, std::abs(field[c][n] - e));
      energy += e * e;
      error += (field[c][n] - e) * (field[c][n] - e);
    }
  }
  // The resynthesis cuts each filter's response at 20 ms; the taps let it ring.
  EXPECT_LT(worst, 1e-3 * peak);
  EXPECT_LT(error, 1e-5 * energy);
}

TEST(ReflectionTapBank, AGlidingTapIsAsSmoothAsItsSource) {
  // One tap walking away at 1.4 m/s (a brisk step: 0.004 ms more delay per ms) while it
  // turns, fed a 2 kHz sine: the output's largest sample-to-sample step stays that of a
  // sine of the same amplitude (Doppler: 2 kHz x 0.996), no click at block edges.
  ReflectionTapBank bank = unshapedTap(0.5);
  std::vector<float> sine(200 * kBlock);
  for (std::size_t n = 0; n < sine.size(); ++n) sine[n] = static_cast<float>(std::sin(2.0 * kPi * 2000.0 * n / kFs));
  const double speed_m_s = 1.4;
  const auto field = run(bank, sine, 200, [&](std::size_t b) {
    const double t = static_cast<double>(b * kBlock) / kFs;
    const double azimuth = 0.5 * t;
    bank.setTargets({{0.010 + speed_m_s * t / 343.0, 0.5, Eigen::Vector3d(std::cos(azimuth), std::sin(azimuth), 0.0)}});
  });
  const std::vector<float>& w = field[0];
  double amplitude = 0.0, step = 0.0;
  for (std::size_t n = 20 * kBlock; n < w.size(); ++n) {
    amplitude = std::max(amplitude, static_cast<double>(std::abs(w[n])));
    step = std::max(step, static_cast<double>(std::abs(w[n] - w[n - 1])));
  }
  ASSERT_GT(amplitude, 0.0);
  EXPECT_LT(step, 1.02 * amplitude * 2.0 * std::sin(kPi * 2000.0 / kFs));
}

TEST(ReflectionTapBank, AMovingTapReadsTheSourceAtItsDelay) {
  // A 500 Hz sine through one tap whose delay glides (a walking pace, then a listener
  // running at Mach 0.5) and jumps (a pose 300 samples away: faster than sound within one
  // block): at every sample the output is the sine at n - delay(n), the delay moving
  // linearly across each block from the last target to the new one.
  ReflectionTapBank bank = unshapedTap(1.0);
  const double w0 = 2.0 * kPi * 500.0 / kFs;
  std::vector<float> sine(120 * kBlock);
  for (std::size_t n = 0; n < sine.size(); ++n) sine[n] = static_cast<float>(std::sin(w0 * n));
  // The delay in samples at the end of block b.
  const auto delayAt = [](std::size_t b) {
    if (b < 40) return 100.0 + 0.5 * static_cast<double>(b);         // walking away
    if (b < 60) return 120.0 + 128.0 * static_cast<double>(b - 40);  // half the block per block
    if (b < 61) return 2680.0 - 300.0;                               // a jump back
    return 2380.0 - 3.0 * static_cast<double>(b - 61);               // walking closer
  };
  const auto field = run(bank, sine, 100, [&](std::size_t b) {
    bank.setTargets({{delayAt(b) / kFs, 1.0, Eigen::Vector3d::UnitX()}});
  });
  // The tap's gain at rest: the W channel over the sine in the first blocks.
  double gain = 0.0, worst = 0.0;
  for (std::size_t b = 5; b < 100; ++b) {
    for (std::size_t n = 0; n < kBlock; ++n) {
      const double u = static_cast<double>(n + 1) / static_cast<double>(kBlock);
      const double delay = delayAt(b - 1) + u * (delayAt(b) - delayAt(b - 1));
      const double expected = std::sin(w0 * (static_cast<double>(b * kBlock + n) - delay));
      const double heard = field[0][b * kBlock + n];
      if (b == 5 && n == kBlock / 4) gain = heard / expected;
      if (gain != 0.0) worst = std::max(worst, std::abs(heard - gain * expected));
    }
  }
  ASSERT_GT(std::abs(gain), 0.1);
  EXPECT_LT(worst, 1e-3 * std::abs(gain));
}

TEST(ReflectionTapBank, ATapsLowPassFollowsItsPoleAndLeavesNoState) {
  // One unshaped tap 40 samples late with a one-pole low-pass, its pole 0.6 for 20
  // blocks, 0.3 for 20, then none: every sample is the reference recursion in transposed
  // form, y[n] = (1 - p) x[n - 40] + s, s = p y[n] with the pole of its block, times the
  // tap's gain (the state a pole leaves feeds the next block's first sample); with none
  // the tap is the delayed source again from the block after. A pole outside [0, 1)
  // keeps the previous target.
  ReflectionTapBank bank = unshapedTap(1.0);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  std::vector<float> source(80 * kBlock);
  for (float& x : source) x = static_cast<float>(normal(rng));
  const auto poleAt = [](std::size_t b) { return b < 20 ? 0.6 : (b < 40 ? 0.3 : 0.0); };
  const auto field = run(bank, source, 80, [&](std::size_t b) {
    bank.setTargets({{40.0 / kFs, 1.0, Eigen::Vector3d::UnitX(), poleAt(b)}});
    if (b == 10) bank.setTargets({{40.0 / kFs, 1.0, Eigen::Vector3d::UnitX(), 1.0}});
    if (b == 30) bank.setTargets({{40.0 / kFs, 1.0, Eigen::Vector3d::UnitX(), NAN}});
  });
  // The tap's gain from the plain blocks at the end.
  const std::size_t probe = 60 * kBlock + 7;
  const double gain = field[0][probe] / source[probe - 40];
  ASSERT_GT(std::abs(gain), 0.1);
  double y = 0.0, state = 0.0, worst = 0.0, peak = 0.0;
  for (std::size_t i = kBlock; i < 80 * kBlock; ++i) {
    const double p = poleAt(i / kBlock);
    y = (1.0 - p) * source[i - 40] + state;
    state = p * y;
    // The first block fades in from silence.
    if (i < 2 * kBlock) continue;
    worst = std::max(worst, std::abs(field[0][i] - gain * y));
    peak = std::max(peak, std::abs(gain * y));
  }
  EXPECT_LT(worst, 1e-4 * peak);
}

TEST(ReflectionTapBank, ManyFilteredMovingTapsMatchAPerSampleReference) {
  // 27, 20, 9 and 43 taps (the filters run eight taps per vector, up to four vectors per
  // pass: one pass of four with a partly filled last vector, one of three, one of two, and
  // one of four then one of two), each with a ninth-order spectral shape, moving at
  // walking pace in delay, level and direction, into a third-order field: every channel
  // equals the sum of the taps computed one sample at a time (the source read at
  // n - delay(n) by cubic Lagrange interpolation, the shape's sections, the gliding
  // amplitude and encoding gains).
  for (const std::size_t count : {27u, 20u, 9u, 43u}) {
  SCOPED_TRACE(count);
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<EarlyReflection> reflections(count);
  for (std::size_t k = 0; k < reflections.size(); ++k) {
    EarlyReflection& r = reflections[k];
    r.time_of_arrival_s = 0.002 + 0.03 * uniform(rng);
    r.level = 0.2 + uniform(rng);
    std::vector<double> segment(96);
    double y = 0.0;
    for (std::size_t n = 0; n < segment.size(); ++n) {
      y = 0.6 * y + normal(rng);
      segment[n] = y * (0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(n) / 95.0));
    }
    const LpcModel shape = fitLpc(segment, kDefaultLpcOrder);
    r.lpc = shape.a;
    r.lpc_gain = shape.gain;
    if (k % 3 != 0) r.sos = allPoleToSections(shape.a, shape.gain);
  }
  ReflectionTapBankOptions options;
  options.block_size = kBlock;
  ReflectionTapBank bank(reflections, options);
  constexpr std::size_t kBlocks = 60;
  std::vector<float> source(kBlocks * kBlock);
  for (float& x : source) x = static_cast<float>(normal(rng));
  // Tap k's target at the end of block b: it walks at up to 1.5 m/s and turns.
  const auto target = [&](std::size_t k, std::size_t b) {
    const double t = static_cast<double>(b * kBlock) / kFs;
    const double turn = 0.3 * t + static_cast<double>(k);
    return TapTarget{reflections[k].time_of_arrival_s + 1.5 / 343.0 * t * std::sin(3.0 * t + static_cast<double>(k)),
                     reflections[k].level * (1.0 + 0.3 * std::sin(5.0 * t + static_cast<double>(k))),
                     Eigen::Vector3d(std::cos(turn), std::sin(turn), 0.4)};
  };
  const auto field = run(bank, source, kBlocks, [&](std::size_t b) {
    std::vector<TapTarget> targets;
    for (std::size_t k = 0; k < reflections.size(); ++k) targets.push_back(target(k, b));
    bank.setTargets(targets);
  });

  std::vector<std::vector<double>> expected(16, std::vector<double>(source.size(), 0.0));
  for (std::size_t k = 0; k < reflections.size(); ++k) {
    EarlyReflection unit = reflections[k];
    unit.level = 1.0;
    unit.time_of_arrival_s = 0.0;
    const double unit_gain = shapeReflectionTap(unit, k, 0.002, 0.020, "test").gain;
    std::vector<double> read(source.size()), amplitude(source.size());
    std::vector<std::vector<double>> gains(source.size());
    for (std::size_t b = 0; b < kBlocks; ++b) {
      const TapTarget from = target(k, b == 0 ? 0 : b - 1), to = target(k, b);
      const std::vector<double> g_from = sn3dHarmonics(3, from.direction.normalized());
      const std::vector<double> g_to = sn3dHarmonics(3, to.direction.normalized());
      for (std::size_t n = 0; n < kBlock; ++n) {
        const double u = static_cast<double>(n + 1) / static_cast<double>(kBlock);
        const std::size_t i = b * kBlock + n;
        const double position = static_cast<double>(i) - kFs * (from.delay_s + u * (to.delay_s - from.delay_s));
        const double whole = std::floor(position), t = position - whole;
        const auto at = [&](double m) {
          const long j = static_cast<long>(whole + m);
          return j >= 0 && j < static_cast<long>(source.size()) ? static_cast<double>(source[static_cast<std::size_t>(j)]) : 0.0;
        };
        read[i] = -t * (t - 1.0) * (t - 2.0) / 6.0 * at(-1) + (t + 1.0) * (t - 1.0) * (t - 2.0) / 2.0 * at(0) -
                  (t + 1.0) * t * (t - 2.0) / 2.0 * at(1) + (t + 1.0) * t * (t - 1.0) / 6.0 * at(2);
        // The first block fades in from silence.
        amplitude[i] = unit_gain * (b == 0 ? u * to.level : from.level + u * (to.level - from.level));
        gains[i].resize(16);
        for (std::size_t c = 0; c < 16; ++c) gains[i][c] = b == 0 ? g_to[c] : g_from[c] + u * (g_to[c] - g_from[c]);
      }
    }
    const std::vector<double> shaped =
        filterSections(!reflections[k].sos.empty() ? reflections[k].sos
                                                   : allPoleToSections(reflections[k].lpc, reflections[k].lpc_gain),
                       read);
    for (std::size_t i = 0; i < source.size(); ++i) {
      for (std::size_t c = 0; c < 16; ++c) expected[c][i] += gains[i][c] * amplitude[i] * shaped[i];
    }
  }
  double peak = 0.0, worst = 0.0;
  for (std::size_t c = 0; c < 16; ++c) {
    for (std::size_t i = 0; i < source.size(); ++i) {
      peak = std::max(peak, std::abs(expected[c][i]));
      worst = std::max(worst, std::abs(field[c][i] - expected[c][i]));
    }
  }
  ASSERT_GT(peak, 1.0);
  EXPECT_LT(worst, 1e-5 * peak);
  }
}

TEST(ReflectionTapBank, ATapThatGoesFadesOverOneBlockAndComesBackWithoutAGlide) {
  EarlyReflection r;
  r.level = 1.0;
  ReflectionTapBankOptions options;
  options.block_size = kBlock;
  options.order = 0;
  ReflectionTapBank bank({r}, options);
  const std::vector<float> ones(40 * kBlock, 1.0f);
  const auto field = run(bank, ones, 40, [&](std::size_t b) {
    const bool heard = b < 10 || b >= 20;
    // Heard again 3 ms further away: it starts there, it does not glide from 10 ms.
    bank.setTargets({{b < 20 ? 0.010 : 0.013, heard ? 1.0 : 0.0, Eigen::Vector3d::UnitX()}});
  });
  const std::vector<float>& w = field[0];
  const double level = w[9 * kBlock];
  ASSERT_GT(level, 0.0);
  // Block 10 fades linearly to zero; blocks 11-19 are silent.
  EXPECT_NEAR(w[10 * kBlock + kBlock / 2 - 1], 0.5 * level, 0.01 * level);
  EXPECT_NEAR(w[11 * kBlock - 1], 0.0, 1e-6);
  for (std::size_t n = 11 * kBlock; n < 20 * kBlock; ++n) ASSERT_EQ(w[n], 0.0f) << n;
  // Block 20 fades in, then the steady level again.
  EXPECT_NEAR(w[21 * kBlock - 1], level, 0.01 * level);
  EXPECT_NEAR(w[30 * kBlock], level, 0.01 * level);
}

TEST(ReflectionTapBank, BadTargetsAndOptions) {
  EarlyReflection r;
  r.level = 1.0;
  ReflectionTapBankOptions options;
  ReflectionTapBank bank({r, r}, options);
  EXPECT_THROW(bank.setTargets({{0.01, 1.0, Eigen::Vector3d::UnitX()}}), InputError);
  // A non-finite target keeps the previous one; a delay past max_delay_s is clamped.
  bank.setTargets({{NAN, 1.0, Eigen::Vector3d::UnitX()}, {0.01, 1.0, Eigen::Vector3d(NAN, 0.0, 0.0)}});
  bank.setTargets({{0.01, 1.0, Eigen::Vector3d::UnitX()}, {30.0, 1.0, Eigen::Vector3d::UnitX()}});
  EXPECT_EQ(bank.clampedTargets(), 1u);
  options.order = 4;
  EXPECT_THROW(ReflectionTapBank({r}, options), InputError);
  options.order = 3;
  options.max_delay_s = 0.0;
  EXPECT_THROW(ReflectionTapBank({r}, options), InputError);
  // A section stable in double precision whose poles round onto the unit circle in the
  // taps' single precision (radius 1 - 1e-9): refused, naming the reflection.
  options.max_delay_s = 0.5;
  EarlyReflection sharp = r;
  sharp.sos = {BiquadSection{1.0, 0.0, 0.0, -2.0 * (1.0 - 1e-9) * std::cos(0.01), (1.0 - 1e-9) * (1.0 - 1e-9)}};
  try {
    ReflectionTapBank refused({r, sharp}, options);
    ADD_FAILURE() << "a filter with poles on the unit circle in single precision was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("reflection 1 has a pole on or outside the unit circle in single precision"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
