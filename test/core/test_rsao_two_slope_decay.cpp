// Bent late decays (metrics/two_slope_decay.h, LateReverbBand::second_share): planted sums
// of two exponential decays per octave band are found with both slopes, and single decays
// stay single. Gaussian band noise is used throughout: one realisation of it scatters an
// octave band's T20 by 4-10 % (ISO 3382-2 A.2), the roughness a measured curve has.
//
// The fit's thresholds (late_reverb.h) were set on the development seeds 1-10; seeds 101-130
// and the other decay pairs of the report are held out.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/metrics/energy_decay.h"
#include "room_reverb/metrics/two_slope_decay.h"
#include "room_reverb/rsao/late_envelope.h"
#include "room_reverb/rsao/late_reverb.h"
#include "synthetic_rir.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::kFs;

namespace {

constexpr std::size_t kOnset = 2400;  // the planted decays start at 50 ms,
constexpr double kMixingS = 0.060;    // the analysis 10 ms later
constexpr double kFirstReflectionS = 0.010;
const double kLn10 = std::log(10.0);

double deltaOf(double t60) { return 3.0 * kLn10 / t60; }

struct PlantedBend {
  std::vector<double> first_t60, second_t60;
  double share = 0.0;  // of the mean square at the decays' start
};

// Band b: sqrt(1 - w) n_1 exp(-delta_1 t) + sqrt(w) n_2 exp(-delta_2 t), n_1 and n_2
// independent Gaussian band noises (their energies add).
std::vector<float> bentDecays(const PlantedBend& p, double noise_floor_db, std::uint32_t seed) {
  const auto bands = standardBands(BandResolution::kOctave);
  const std::size_t length = 4 * 48000;
  const std::vector<float> first = room_reverb::test::bandwiseDecayNoise(length, bands, p.first_t60, kOnset, seed);
  std::vector<float> rir(length, 0.0f);
  if (p.share > 0.0) {
    const std::vector<float> second =
        room_reverb::test::bandwiseDecayNoise(length, bands, p.second_t60, kOnset, seed + 5000);
    for (std::size_t n = 0; n < length; ++n) {
      rir[n] = static_cast<float>(std::sqrt(1.0 - p.share) * first[n] + std::sqrt(p.share) * second[n]);
    }
  } else {
    rir = first;
  }
  room_reverb::test::addNoiseFloor(rir, noise_floor_db, seed + 1);
  return rir;
}

// A model's energy remaining after t' = t - mixing time: a sum of exponential energy terms
// (share_i of the envelope's energy at t' = 0, decay constant delta_i).
struct DecayTerms {
  std::vector<double> share, delta;
  double remaining(double t) const {
    double sum = 0.0;
    for (std::size_t i = 0; i < share.size(); ++i) sum += share[i] / (2.0 * delta[i]) * std::exp(-2.0 * delta[i] * t);
    return sum;
  }
  // The decay time of a least-squares line through the curve (1 ms steps) between two
  // levels, as EnergyDecay::decayTimeS reads a measured one.
  double decayTime(double start_db, double end_db) const {
    const double total = remaining(0.0);
    double s_t = 0, s_l = 0, s_tt = 0, s_tl = 0, n = 0;
    for (double t = 0.0; t < 30.0; t += 0.001) {
      const double level = 10.0 * std::log10(remaining(t) / total);
      if (level > start_db) continue;
      if (level < end_db) break;
      s_t += t, s_l += level, s_tt += t * t, s_tl += t * level, n += 1;
    }
    return -60.0 * (n * s_tt - s_t * s_t) / (n * s_tl - s_t * s_l);
  }
};

DecayTerms estimatedTerms(const LateReverbBand& band) {
  if (band.second_share <= 0.0) return {{1.0}, {band.decay_constant_per_s}};
  return {{1.0 - band.second_share, band.second_share}, {band.first_decay_constant_per_s, band.second_decay_constant_per_s}};
}

// The spans of the decay a listener and ISO 3382-1 read: the first 10 dB (EDT-like, from
// the mixing time), -5 to -25 dB (T20) and -5 to -35 dB (T30).
constexpr double kSpans[3][2] = {{0.0, -10.0}, {-5.0, -25.0}, {-5.0, -35.0}};

// The planted RIR's own curves from the mixing time, per octave band: the measurement a
// model of its late part must reproduce (one realisation of the noise, not its expectation).
std::vector<std::array<double, 3>> measuredDecayTimes(const std::vector<float>& rir) {
  const auto split = BandFilterBank(standardBands(BandResolution::kOctave), kFs).split(rir);
  std::vector<std::array<double, 3>> times;
  for (const std::vector<float>& band : split) {
    const EnergyDecay decay(band, static_cast<std::size_t>(std::lround(kMixingS * kFs)), kFs);
    times.push_back({decay.decayTimeS(kSpans[0][0], kSpans[0][1]), decay.decayTimeS(kSpans[1][0], kSpans[1][1]),
                     decay.decayTimeS(kSpans[2][0], kSpans[2][1])});
  }
  return times;
}

// The worst relative error of the model's three decay times against the measured ones.
double curveError(const DecayTerms& model, const std::array<double, 3>& measured) {
  double worst = 0.0;
  for (int i = 0; i < 3; ++i) {
    worst = std::max(worst, std::abs(model.decayTime(kSpans[i][0], kSpans[i][1]) / measured[i] - 1.0));
  }
  return worst;
}

const PlantedBend kCoupled{{0.9, 0.8, 0.7, 0.6, 0.5, 0.45, 0.4, 0.3, 0.2}, {2.4, 2.2, 2.0, 1.8, 1.5, 1.3, 1.1, 0.8, 0.5}, 0.06};
const PlantedBend kSingle{{1.8, 1.6, 1.4, 1.2, 1.0, 0.9, 0.8, 0.6, 0.4}, {}, 0.0};

}  // namespace

TEST(TwoSlopeFit, RecoversAnExactSumOfTwoExponentials) {
  // An exact energy envelope (no noise): R(t) is the planted sum, so both fits are exact.
  const double a1 = 2.0 * deltaOf(0.5), a2 = 2.0 * deltaOf(1.6), w = 0.1;
  std::vector<float> h(3 * 48000);
  for (std::size_t n = 0; n < h.size(); ++n) {
    const double t = n / kFs;
    h[n] = static_cast<float>(std::sqrt((1.0 - w) * std::exp(-a1 * t) + w * std::exp(-a2 * t)));
  }
  const EnergyDecay decay(h, 0, kFs);
  ASSERT_TRUE(decay.valid());
  const TwoSlopeFit fit = fitTwoSlopes(decay, -40.0);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.fast_rate_per_s / a1, 1.0, 0.05);
  EXPECT_NEAR(fit.slow_rate_per_s / a2, 1.0, 0.05);
  // Energy remaining at 0 of each term: share / rate of the envelope's energy.
  const double total = (1.0 - w) / a1 + w / a2;
  EXPECT_NEAR(fit.slow_energy / (fit.fast_energy + fit.slow_energy), (w / a2) / total, 0.02);
  EXPECT_LT(fit.rms_error_db, 0.1);
  EXPECT_GT(fit.one_rms_error_db, 0.5);
  EXPECT_GT(fit.crossover_s(), 0.0);
  EXPECT_LT(fit.crossover_s(), fit.end_s);
}

TEST(TwoSlopeFit, CurveThatNeverReachesTheDepthIsNotFitted) {
  std::vector<float> h(48000);
  for (std::size_t n = 0; n < h.size(); ++n) h[n] = static_cast<float>(std::exp(-deltaOf(1.0) * n / kFs));
  const EnergyDecay decay(h, 0, kFs);
  EXPECT_FALSE(fitTwoSlopes(decay, -200.0).valid);
  EXPECT_FALSE(fitTwoSlopes(decay, 0.0).valid);
}

TEST(LateReverbTwoSlopes, PlantedBentDecaysGetBothSlopes) {
  const std::vector<float> rir = bentDecays(kCoupled, -75.0, 3);
  const LateReverb late = estimateLateReverb(rir, kFirstReflectionS, kMixingS);
  const std::vector<std::array<double, 3>> measured = measuredDecayTimes(rir);
  for (std::size_t b = 1; b + 1 < late.bands.size(); ++b) {
    const LateReverbBand& band = late.bands[b];
    SCOPED_TRACE(band.center_hz);
    ASSERT_TRUE(band.reliable) << band.reason;
    ASSERT_GT(band.second_share, 0.0);
    // The curve, not each parameter: with one realisation of band noise a faster first
    // slope with less energy fits as well as the planted pair. The model's EDT, T20 and
    // T30 from the mixing time against the planted RIR's own.
    const double error = curveError(estimatedTerms(band), measured[b]);
    LateReverbBand one = band;
    one.second_share = 0.0;
    // Measured on this seed: within 20 % in every band, where one slope misses by up to
    // 94 % (the report: p95 19 % development, 25 % held-out; one slope 74 % and 84 %).
    EXPECT_LT(error, 0.25);
    EXPECT_LT(error, curveError(estimatedTerms(one), measured[b]));
    EXPECT_NEAR(band.second_decay_constant_per_s / deltaOf(kCoupled.second_t60[b]), 1.0, 0.35);
    // The paper's line over the first 20 dB lies between the two.
    EXPECT_LT(band.decay_constant_per_s, band.first_decay_constant_per_s);
    EXPECT_GT(band.decay_constant_per_s, band.second_decay_constant_per_s);
    // 60 dB of the envelope takes longer than the first slope's T60.
    EXPECT_GT(lateDecayLengthS(band), kCoupled.first_t60[b]);
  }
}

TEST(LateReverbTwoSlopes, SingleDecaysStaySingleAndTheOptionTurnsTheFitOff) {
  const std::vector<float> rir = bentDecays(kSingle, -75.0, 4);
  const LateReverb late = estimateLateReverb(rir, kFirstReflectionS, kMixingS);
  for (const LateReverbBand& band : late.bands) {
    EXPECT_EQ(band.second_share, 0.0) << band.center_hz;
    EXPECT_EQ(band.first_decay_constant_per_s, 0.0);
  }
  LateReverbOptions one;
  one.two_slopes = false;
  const LateReverb paper = estimateLateReverb(bentDecays(kCoupled, -75.0, 3), kFirstReflectionS, kMixingS, one);
  for (const LateReverbBand& band : paper.bands) EXPECT_EQ(band.second_share, 0.0) << band.center_hz;
}

TEST(LateReverbTwoSlopes, BadTwoSlopeOptionsAreRefused) {
  const std::vector<float> rir = bentDecays(kSingle, -75.0, 4);
  LateReverbOptions o;
  o.min_two_slope_depth_db = 50.0;  // deeper than two_slope_depth_db
  room_reverb::test::expectInputError([&] { estimateLateReverb(rir, kFirstReflectionS, kMixingS, o); },
                                      {"two-slope fit", "min_two_slope_depth_db <= two_slope_depth_db"});
  o = {};
  o.max_two_slope_error_ratio = 0.0;
  room_reverb::test::expectInputError([&] { estimateLateReverb(rir, kFirstReflectionS, kMixingS, o); },
                                      {"max_two_slope_error_ratio > 0"});
  o.two_slopes = false;  // unused settings of a fit that is off are not checked
  EXPECT_NO_THROW(estimateLateReverb(rir, kFirstReflectionS, kMixingS, o));
}

// ROOM_REVERB_TWO_SLOPE_REPORT=1: bands called bent, over development (1-10) and held-out
// (101-130) seeds, for single decays and for three bends (the coupled one above, a weak
// bend and a strong late tail), at a 75 dB and a 50 dB noise floor.
TEST(LateReverbTwoSlopes, Report) {
  if (!std::getenv("ROOM_REVERB_TWO_SLOPE_REPORT")) GTEST_SKIP() << "set ROOM_REVERB_TWO_SLOPE_REPORT=1";
  const PlantedBend weak{{1.0, 0.9, 0.8, 0.7, 0.6, 0.55, 0.5, 0.4, 0.3}, {1.5, 1.35, 1.2, 1.05, 0.9, 0.8, 0.75, 0.6, 0.45}, 0.2};
  const PlantedBend tail{{0.6, 0.55, 0.5, 0.45, 0.4, 0.35, 0.3, 0.25, 0.2}, {3.0, 2.8, 2.6, 2.4, 2.0, 1.8, 1.5, 1.0, 0.6}, 0.01};
  const struct { const char* name; PlantedBend bend; } cases[] = {{"single", kSingle}, {"coupled", kCoupled},
                                                                  {"weak", weak}, {"tail", tail}};
  const struct { const char* name; std::uint32_t first, count; } sets[] = {{"development", 1, 10}, {"held-out", 101, 30}};
  for (double floor_db : {-75.0, -50.0}) {
    for (const auto& c : cases) {
      for (const auto& set : sets) {
        int bent = 0, reliable = 0;
        std::vector<double> errors, one_errors;
        for (std::uint32_t seed = set.first; seed < set.first + set.count; ++seed) {
          const std::vector<float> rir = bentDecays(c.bend, floor_db, seed);
          const LateReverb late = estimateLateReverb(rir, kFirstReflectionS, kMixingS);
          const std::vector<std::array<double, 3>> measured = measuredDecayTimes(rir);
          for (std::size_t b = 1; b + 1 < late.bands.size(); ++b) {
            const LateReverbBand& band = late.bands[b];
            if (!band.reliable) continue;
            ++reliable;
            if (band.second_share > 0.0) ++bent;
            LateReverbBand one = band;
            one.second_share = 0.0;
            errors.push_back(curveError(estimatedTerms(band), measured[b]));
            one_errors.push_back(curveError(estimatedTerms(one), measured[b]));
          }
        }
        std::sort(errors.begin(), errors.end());
        std::sort(one_errors.begin(), one_errors.end());
        auto p95 = [](const std::vector<double>& v) { return v.empty() ? 0.0 : 100.0 * v[(v.size() * 95) / 100]; };
        std::printf("floor %3.0f dB  %-8s %-12s bent %3d of %3d reliable bands (125 Hz-8 kHz); "
                    "EDT/T20/T30 error p95 %4.1f %% (one slope: %4.1f %%), worst %4.1f %% (%4.1f %%)\n",
                    floor_db, c.name, set.name, bent, reliable, p95(errors), p95(one_errors),
                    errors.empty() ? 0.0 : 100.0 * errors.back(), one_errors.empty() ? 0.0 : 100.0 * one_errors.back());
      }
    }
  }
}
