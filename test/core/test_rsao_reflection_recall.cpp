// The RSAO estimator's early reflections on synthetic B-format rooms whose image sources
// are known (reflection_rooms.h): recall of the reflections any estimator should resolve,
// their time and direction errors, and the share of reported reflections that are real
// (reflection_score.h). The development set is what the detection may be tuned on; the
// held-out set (other seeds, shapes, absorptions, a reflector panel) is not.
//
// Report over both sets, with the misses (ROOM_REVERB_CAPTURE_FLAWS=loudspeaker,
// microphone or both adds what a real capture holds and the rooms do not:
// addCaptureFlaws below):
//   ROOM_REVERB_RSAO_REPORT=1 [ROOM_REVERB_PAPER_ONSETS=1] [ROOM_REVERB_CAPTURE_FLAWS=both] .ws/devel/lib/room_reverb/test_rsao_reflection_recall --gtest_filter='*Report*'
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "reflection_rooms.h"
#include "reflection_score.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/rsao/lpc.h"
#include "room_reverb/rsao/reflection_tap.h"
#include "room_reverb/rsao/rsao_estimator.h"

using namespace room_reverb::core;
using room_reverb::test::ReflectionRoom;
using room_reverb::test::ReflectionRoomSet;
using room_reverb::test::ReflectionScore;

namespace {

constexpr double kFs = 48000.0;

ReflectionScore scoreRoom(const ReflectionRoom& room, const RsaoOptions& options) {
  const Rsao rsao = estimateRsao(room.ambix, AmbisonicFormat::kAmbiX, options);
  return room_reverb::test::scoreReflections(room, rsao.reflections);
}

RsaoOptions matchedPursuit() {
  RsaoOptions options;
  options.early.onset_method = OnsetMethod::kMatchedPursuit;
  return options;
}

// RBJ cookbook biquads (Bristow-Johnson, "Audio EQ Cookbook"), normalised to a0 = 1.
BiquadSection highPass(double f_hz, double q) {
  const double w = 2.0 * M_PI * f_hz / kFs, alpha = std::sin(w) / (2.0 * q), c = std::cos(w), a0 = 1.0 + alpha;
  return {(1.0 + c) / 2.0 / a0, -(1.0 + c) / a0, (1.0 + c) / 2.0 / a0, -2.0 * c / a0, (1.0 - alpha) / a0};
}
BiquadSection peaking(double f_hz, double q, double gain_db) {
  const double a = std::pow(10.0, gain_db / 40.0), w = 2.0 * M_PI * f_hz / kFs, alpha = std::sin(w) / (2.0 * q);
  const double c = std::cos(w), a0 = 1.0 + alpha / a;
  return {(1.0 + alpha * a) / a0, -2.0 * c / a0, (1.0 - alpha * a) / a0, -2.0 * c / a0, (1.0 - alpha / a) / a0};
}
BiquadSection lowPass(double f_hz, double q) {
  const double w = 2.0 * M_PI * f_hz / kFs, alpha = std::sin(w) / (2.0 * q), c = std::cos(w), a0 = 1.0 + alpha;
  return {(1.0 - c) / 2.0 / a0, (1.0 - c) / a0, (1.0 - c) / 2.0 / a0, -2.0 * c / a0, (1.0 - alpha) / a0};
}

// What a real capture adds that the rooms do not hold: a loudspeaker's response in every
// arrival (an 80 Hz high-pass and a ringing +6 dB resonance at 3 kHz, Q 4), and a
// tetrahedral microphone's B-format errors (X, Y and Z each off by up to +-0.5 dB, and
// rolled off above 10 kHz against W).
void addCaptureFlaws(AudioBuffer& ambix, unsigned seed, bool loudspeaker_flaws, bool microphone_flaws) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> gain_db(-0.5, 0.5);
  const std::vector<BiquadSection> loudspeaker = {highPass(80.0, 0.707), peaking(3000.0, 4.0, 6.0)};
  for (std::size_t c = 0; c < 4; ++c) {
    std::vector<BiquadSection> chain;
    if (loudspeaker_flaws) chain = loudspeaker;
    if (c > 0 && microphone_flaws) chain.push_back(lowPass(10000.0, 0.707));
    std::vector<double> x(ambix.channels[c].begin(), ambix.channels[c].end());
    x = filterSections(chain, x);
    const double g = c > 0 && microphone_flaws ? std::pow(10.0, gain_db(rng) / 20.0) : 1.0;
    for (std::size_t n = 0; n < x.size(); ++n) ambix.channels[c][n] = static_cast<float>(g * x[n]);
  }
}

ReflectionScore scoreSet(ReflectionRoomSet set, const RsaoOptions& options) {
  ReflectionScore total;
  for (std::size_t i = 0; i < room_reverb::test::reflectionRoomCount(set); ++i) {
    total.add(scoreRoom(room_reverb::test::reflectionRoom(set, i), options));
  }
  return total;
}

}  // namespace

TEST(ReflectionRooms, TheDirectSoundAndAFirstOrderReflectionAreWhereTheGeometryPutsThem) {
  const ReflectionRoom room = room_reverb::test::reflectionRoom(ReflectionRoomSet::kDevelopment, 0);
  ASSERT_GT(room.images.size(), 30u);
  const auto& direct = room.images.front();
  EXPECT_EQ(direct.order, 0);
  // W around the direct sound holds its pulse: energy level^2 within 1 % (the noise
  // floor is 60 dB down, the diffuse tail has not started).
  const auto centre = static_cast<std::size_t>(std::lround(direct.time_s * kFs));
  double energy = 0.0;
  Eigen::Vector3d intensity = Eigen::Vector3d::Zero();
  for (std::size_t n = centre - 40; n <= centre + 40; ++n) {
    const double w = room.ambix.channels[0][n];
    energy += w * w;
    intensity += w * Eigen::Vector3d(room.ambix.channels[3][n], room.ambix.channels[1][n], room.ambix.channels[2][n]);
  }
  EXPECT_NEAR(std::sqrt(energy) / direct.level, 1.0, 0.01);
  // The active intensity points to the direct sound's true direction (within 1 degree).
  EXPECT_GT(intensity.normalized().dot(direct.direction), std::cos(M_PI / 180.0));
  // Every first-order image is a single bounce: 1 to 6 of them (the source inside the box).
  int first_order = 0;
  for (const auto& a : room.images) first_order += a.order == 1 ? 1 : 0;
  EXPECT_EQ(first_order, 6);
}

TEST(ReflectionRooms, TheSetsAreDeterministicAndHoldTheirKinds) {
  const ReflectionRoom a = room_reverb::test::reflectionRoom(ReflectionRoomSet::kHeldOut, 3);
  const ReflectionRoom b = room_reverb::test::reflectionRoom(ReflectionRoomSet::kHeldOut, 3);
  EXPECT_EQ(a.ambix.channels, b.ambix.channels);
  EXPECT_GE(room_reverb::test::reflectionRoomCount(ReflectionRoomSet::kDevelopment), 15u);
  EXPECT_GE(room_reverb::test::reflectionRoomCount(ReflectionRoomSet::kHeldOut), 15u);
}

// Development rooms, with the tool's default selection (at most 20 reflections, strongest first):
// matching pursuit finds 89 of 94 (the five it leaves out are below the 20 strongest),
// times within 0.007 ms and directions within 1.1 degrees at the 95th percentile, every
// reported reflection real; the paper's group-delay onsets find 71 with 0.39 ms and 66
// degrees (a reflection timed between two and pointed at neither).
TEST(ReflectionRecall, MatchedPursuitOnTheDevelopmentRooms) {
  const ReflectionScore pursuit = scoreSet(ReflectionRoomSet::kDevelopment, matchedPursuit());
  EXPECT_EQ(pursuit.resolvable, 94);
  EXPECT_GE(pursuit.found, 89) << pursuit.summary();
  EXPECT_LT(pursuit.toaP95Ms(), 0.02) << pursuit.summary();
  EXPECT_LT(pursuit.directionP95Deg(), 2.0) << pursuit.summary();
  EXPECT_EQ(pursuit.real, pursuit.reported) << pursuit.summary();

  RsaoOptions paper;
  paper.early.onset_method = OnsetMethod::kGroupDelay;
  const ReflectionScore group_delay = scoreSet(ReflectionRoomSet::kDevelopment, paper);
  EXPECT_LE(group_delay.found, 75) << group_delay.summary();
  EXPECT_GT(group_delay.directionP95Deg(), 20.0) << group_delay.summary();
}

// Development rooms: each matched-pursuit reflection's level is its own energy in W, the
// rendered pulse's (ImageArrival::level): for the reflections found (first and second
// order within 30 ms, at most 14 dB below the direct sound, a report within 0.05 ms), the
// error of level re the direct sound, in dB. 217 reflections: median 0.60 dB, p95 4.6 dB;
// levels from the 2 ms analysis window, which also holds a neighbour 0.5 ms away (the
// close-pair rooms) or the direct sound (the near-direct rooms), give 2.5 dB and 6.3 dB.
TEST(ReflectionRecall, MatchedPursuitLevelsAreTheArrivalsOwn) {
  RsaoOptions options = matchedPursuit();
  options.early.max_reflections = 40;
  std::vector<double> errors_db;
  for (std::size_t i = 0; i < room_reverb::test::reflectionRoomCount(ReflectionRoomSet::kDevelopment); ++i) {
    const ReflectionRoom room = room_reverb::test::reflectionRoom(ReflectionRoomSet::kDevelopment, i);
    const Rsao rsao = estimateRsao(room.ambix, AmbisonicFormat::kAmbiX, options);
    const auto& direct = room.images.front();
    for (const auto& a : room.images) {
      if (a.order < 1 || a.order > 2 || a.time_s - direct.time_s > 0.03 || a.level < direct.level * std::pow(10.0, -14.0 / 20.0))
        continue;
      for (std::size_t k = 1; k < rsao.reflections.size(); ++k) {
        if (std::abs(rsao.reflections[k].time_of_arrival_s - a.time_s) > 0.00005) continue;
        const double estimated = rsao.reflections[k].level / rsao.reflections[0].level;
        errors_db.push_back(std::abs(20.0 * std::log10(estimated / (a.level / direct.level))));
        break;
      }
    }
  }
  ASSERT_GE(errors_db.size(), 80u);
  std::sort(errors_db.begin(), errors_db.end());
  const double median = errors_db[errors_db.size() / 2];
  const double p95 = errors_db[static_cast<std::size_t>(0.95 * static_cast<double>(errors_db.size() - 1))];
  std::printf("[ levels   ] %zu reflections, |error| median %.2f dB, p95 %.2f dB, max %.2f dB\n", errors_db.size(), median,
              p95, errors_db.back());
  EXPECT_LT(median, 1.0);
  EXPECT_LT(p95, 5.5);
}

// Each tap's spectral shape against its arrival's, per octave 125 Hz-4 kHz: the band energy
// of the tap as the resynthesis plays it (reflection_tap.h) over the truth's (the rooms'
// pulses are flat to 20 kHz in the shoeboxes). A 2 ms window of the RIR holds the
// arrival's neighbours, whose low frequencies add there coherently (the paper's fit of it
// puts +2.1 dB at 125 Hz into the median tap); each tap is fitted on its arrival alone (W
// less the pursuit's other arrivals, early_reflections.h): +0.60, +0.56 and +0.42 dB at 125,
// 250 and 500 Hz with the spectrum held below 1/D, +0.46, +0.42 and +0.32 dB with the
// paper's fit of that window. Development shoeboxes, every estimated arrival within 0.1 ms
// of one.
TEST(ReflectionRecall, TapsCarryTheArrivalsLowFrequencies) {
  const BandFilterBank bank = [] {
    std::vector<FrequencyBand> bands;
    for (const FrequencyBand& b : standardBands(BandResolution::kOctave)) {
      if (b.nominal_hz >= 125.0 && b.nominal_hz <= 4000.0) bands.push_back(b);
    }
    return BandFilterBank(bands, kFs);
  }();
  const auto bandEnergies = [&](const std::vector<float>& x) {
    std::vector<double> energy;
    for (const std::vector<float>& band : bank.split(x)) {
      double e = 0.0;
      for (float v : band) e += static_cast<double>(v) * v;
      energy.push_back(e);
    }
    return energy;
  };
  // The share of a flat arrival's energy in each band, from the rooms' own pulse.
  const room_reverb::test::ArrivalPulse truth = room_reverb::test::renderArrivalPulse(4800.0, 1.0, 0, 0.0);
  std::vector<float> pulse(9600, 0.0f);
  double pulse_energy = 0.0;
  for (std::size_t i = 0; i < truth.samples.size(); ++i) {
    pulse[static_cast<std::size_t>(truth.first) + i] = static_cast<float>(truth.samples[i]);
    pulse_energy += truth.samples[i] * truth.samples[i];
  }
  const std::vector<double> share = bandEnergies(pulse);
  const auto medianErrors = [&](const RsaoOptions& options) {
    std::vector<std::vector<double>> errors(share.size());
    for (std::size_t i = 0; i < 8; ++i) {  // the shoeboxes
      const ReflectionRoom room = room_reverb::test::reflectionRoom(ReflectionRoomSet::kDevelopment, i);
      const Rsao rsao = estimateRsao(room.ambix, AmbisonicFormat::kAmbiX, options);
      for (std::size_t k = 0; k < rsao.reflections.size(); ++k) {
        const EarlyReflection& r = rsao.reflections[k];
        const auto match = std::find_if(room.images.begin(), room.images.end(), [&](const auto& a) {
          return std::abs(a.time_s - r.time_of_arrival_s) < 0.0001;
        });
        if (match == room.images.end()) continue;
        const ReflectionTap tap = shapeReflectionTap(r, k, options.early.analysis_window_s, 0.02, "tap");
        std::vector<float> played(tap.samples.size() + 9600, 0.0f);
        for (std::size_t n = 0; n < tap.samples.size(); ++n) played[4800 + n] = static_cast<float>(tap.gain * tap.samples[n]);
        const std::vector<double> energy = bandEnergies(played);
        for (std::size_t b = 0; b < share.size(); ++b) {
          const double truth = match->level * match->level * share[b] / pulse_energy;
          errors[b].push_back(10.0 * std::log10(energy[b] / truth));
        }
      }
    }
    std::vector<double> medians;
    for (std::vector<double>& e : errors) {
      std::sort(e.begin(), e.end());
      medians.push_back(e[e.size() / 2]);
    }
    return medians;
  };
  RsaoOptions paper = matchedPursuit();
  paper.early.lpc_flat_below_hz = 0.0;
  const std::vector<double> held = medianErrors(matchedPursuit()), whole = medianErrors(paper);
  std::printf("[ measured ] median tap's band energy over its arrival's, 125 Hz-4 kHz:");
  for (double e : held) std::printf(" %+.2f", e);
  std::printf(" dB (the paper's fit:");
  for (double e : whole) std::printf(" %+.2f", e);
  std::printf(" dB)\n");
  for (std::size_t b = 0; b < 3; ++b) {  // 125-500 Hz
    EXPECT_LT(std::abs(held[b]), 1.0) << b;
    EXPECT_LT(std::abs(whole[b]), 1.0) << b;
  }
  for (std::size_t b = 3; b < held.size(); ++b) EXPECT_LT(std::abs(held[b]), 1.0) << b;
}

// Held-out rooms (nothing was tuned on them), with room for 40 reflections so that the
// count is the detector's, not the selection's: the targets (95 % found, time p95
// under 0.05 ms, direction p95 under 3 degrees, at most one in ten reported unreal).
TEST(ReflectionRecall, MatchedPursuitOnTheHeldOutRooms) {
  RsaoOptions options = matchedPursuit();
  options.early.max_reflections = 40;
  const ReflectionScore score = scoreSet(ReflectionRoomSet::kHeldOut, options);
  EXPECT_EQ(score.resolvable, 116);
  EXPECT_GE(score.recall(), 0.95) << score.summary();
  EXPECT_LT(score.toaP95Ms(), 0.05) << score.summary();
  EXPECT_LT(score.directionP95Deg(), 3.0) << score.summary();
  EXPECT_GE(score.precision(), 0.9) << score.summary();
}

// A microphone whose directional channels respond otherwise than W (X, Y, Z rolled off
// above 10 kHz and off by up to +-0.5 dB): the arrivals keep their directions within what
// the gain errors alone allow (up to 3.3 degrees between two axes). Subtracted with W's
// shape in every channel, the roll-off's leftovers leaned the next arrivals: 4.7 degrees.
TEST(ReflectionRecall, MatchedPursuitWithAMicrophonesChannelErrors) {
  RsaoOptions options = matchedPursuit();
  ReflectionScore total;
  for (std::size_t i = 0; i < room_reverb::test::reflectionRoomCount(ReflectionRoomSet::kDevelopment); ++i) {
    ReflectionRoom room = room_reverb::test::reflectionRoom(ReflectionRoomSet::kDevelopment, i);
    addCaptureFlaws(room.ambix, 1000u + static_cast<unsigned>(i), false, true);
    total.add(scoreRoom(room, options));
  }
  std::printf("[ measured ] development rooms, microphone errors: %s\n", total.summary().c_str());
  EXPECT_GE(total.recall(), 0.95) << total.summary();
  EXPECT_LT(total.directionP95Deg(), 3.3) << total.summary();
  EXPECT_GE(total.precision(), 0.9) << total.summary();
}

TEST(ReflectionRecallReport, BothSets) {
  if (!std::getenv("ROOM_REVERB_RSAO_REPORT")) GTEST_SKIP() << "set ROOM_REVERB_RSAO_REPORT=1 for the report";
  const bool paper = std::getenv("ROOM_REVERB_PAPER_ONSETS") != nullptr;
  const bool flaws = std::getenv("ROOM_REVERB_CAPTURE_FLAWS") != nullptr;
  const std::string flaws_kind = flaws ? std::getenv("ROOM_REVERB_CAPTURE_FLAWS") : "";
  RsaoOptions options = matchedPursuit();
  if (paper) options.early.onset_method = OnsetMethod::kGroupDelay;
  if (const char* n = std::getenv("ROOM_REVERB_MAX_REFLECTIONS")) options.early.max_reflections = std::strtoul(n, nullptr, 10);
  if (const char* v = std::getenv("ROOM_REVERB_DETECTION_SNR_DB")) options.early.matched.min_detection_snr_db = std::atof(v);
  if (const char* v = std::getenv("ROOM_REVERB_EXPLAINED_SHARE")) options.early.matched.min_explained_share = std::atof(v);
  for (const auto set : {ReflectionRoomSet::kDevelopment, ReflectionRoomSet::kHeldOut}) {
    const char* name = set == ReflectionRoomSet::kDevelopment ? "development" : "held-out";
    ReflectionScore total;
    for (std::size_t i = 0; i < room_reverb::test::reflectionRoomCount(set); ++i) {
      ReflectionRoom room = room_reverb::test::reflectionRoom(set, i);
      if (flaws) addCaptureFlaws(room.ambix, 1000u + static_cast<unsigned>(i), flaws_kind != "microphone", flaws_kind != "loudspeaker");
      const ReflectionScore score = scoreRoom(room, options);
      std::printf("[ room     ] %-15s %s\n", room.name.c_str(), score.summary().c_str());
      total.add(score);
    }
    std::printf("[ report   ] %s, %s: %s\n", name, paper ? "paper onsets" : "matched pursuit", total.summary().c_str());
    for (const auto& m : total.misses) {
      std::printf("[ miss     ] %-15s %6.2f ms  %6.1f dB  order %d  comparable neighbour %.2f ms, nearest report %+.2f ms\n",
                  m.room.c_str(), m.delay_ms, m.level_db, m.order, m.neighbour_ms, m.nearest_report_ms);
    }
  }
}
