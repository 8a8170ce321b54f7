// The whole RSAO estimator (estimateRsao): format handling, resampling, the mixing time
// feeding the early part, the early-energy course, on synthetic rooms with known truth and
// on the bundled measured B-format RIRs; and every bad input a user can give it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/metrics/impulse_response_metrics.h"
#include "room_reverb/rsao/rsao_estimator.h"
#include "room_reverb/rsao/rsao_resynthesis.h"
#include "shoebox.h"
#include "synthetic_rir.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A 7.2 x 5.1 x 3.0 m shoebox, fast mode (image sources to order 3 plus the parametric
// Eyring tail): the direct sound's time and direction and each band's T60 are known.
struct SyntheticRoom {
  SimulationResult result;
  Eigen::Vector3d source{5.3, 3.6, 1.6}, listener{2.2, 1.9, 1.3};
};

const SyntheticRoom& syntheticRoom() {
  static const SyntheticRoom room = [] {
    SyntheticRoom r;
    const AcousticScene scene(room_reverb::test::shoeboxMesh({7.2, 5.1, 3.0}),
                              room_reverb::test::uniformLibrary(0.15, 0.1));
    SimulationSettings settings;
    settings.mode = SimulationMode::kEyring;
    settings.duration_s = 1.5;
    r.result = simulateRoom(scene, r.source, r.listener, settings);
    // Measurement noise 70 dB below the direct sound's peak.
    auto& ir = r.result.impulse_response;
    float peak = 0.0f;
    for (float v : ir.channels[0]) peak = std::max(peak, std::abs(v));
    for (std::size_t c = 0; c < 4; ++c) {
      const auto noise = room_reverb::test::whiteNoise(ir.frameCount(), 40 + static_cast<std::uint32_t>(c));
      for (std::size_t n = 0; n < noise.size(); ++n) ir.channels[c][n] += 3e-4f * peak * noise[n];
    }
    return r;
  }();
  return room;
}

double angleDeg(const Eigen::Vector3d& a, double azimuth, double elevation) {
  const Eigen::Vector3d b(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                          std::sin(elevation));
  return std::acos(std::clamp(a.normalized().dot(b), -1.0, 1.0)) * 180.0 / kPi;
}

struct MeasuredCase {
  const char* file;
  AmbisonicFormat format;  // what the channel energies say (data/README.md)
};

const std::vector<MeasuredCase>& measuredCases() {
  static const std::vector<MeasuredCase> cases = {
      {"dixon_studio_theatre_r1.wav", AmbisonicFormat::kFuMa},
      {"jack_lyons_concert_hall_lp1.wav", AmbisonicFormat::kAmbiX},
      {"st_andrews_church.wav", AmbisonicFormat::kFuMa},
      {"terrys_typing_room.wav", AmbisonicFormat::kFuMa},
      {"tyndall_bruce_monument.wav", AmbisonicFormat::kFuMa},
  };
  return cases;
}

AudioBuffer measured(const MeasuredCase& c) {
  return readAudioFile(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/rirs/bformat/" + c.file);
}

}  // namespace

TEST(RsaoEstimator, SyntheticRoomDirectSoundMixingTimeAndDecays) {
  const SyntheticRoom& room = syntheticRoom();
  const Rsao rsao = estimateRsao(room.result.impulse_response, AmbisonicFormat::kAmbiX);
  const Eigen::Vector3d to_source = room.source - room.listener;
  const double direct_s = to_source.norm() / room.result.speed_of_sound_m_s;
  ASSERT_FALSE(rsao.reflections.empty());
  EXPECT_NEAR(rsao.reflections[0].time_of_arrival_s, direct_s, 1e-4);
  EXPECT_LT(angleDeg(to_source, rsao.reflections[0].azimuth_rad, rsao.reflections[0].elevation_rad), 5.0);
  // The mixing time falls after the first reflections and within the first 100 ms.
  EXPECT_GT(rsao.late.mixing_time_s, rsao.reflections[0].time_of_arrival_s + 0.005);
  EXPECT_LT(rsao.late.mixing_time_s, 0.15);
  for (std::size_t k = 1; k < rsao.reflections.size(); ++k) {
    EXPECT_LE(rsao.reflections[k].time_of_arrival_s, rsao.late.mixing_time_s);
  }
  // Each band decays as the simulation's Eyring tail, within the 5 % where the
  // octave filter bank can separate the bands: at 63 Hz the tail holds too few modes in
  // 1.5 s, and the 16 kHz band also sees the slower 8 kHz band across their crossover
  // (+12 % here), so 15 % there.
  ASSERT_EQ(rsao.late.bands.size(), 9u);
  for (std::size_t b = 0; b < 9; ++b) {
    ASSERT_TRUE(rsao.late.bands[b].reliable) << rsao.late.bands[b].center_hz << ": " << rsao.late.bands[b].reason;
    EXPECT_NEAR(rsao.late.bands[b].t60_s / room.result.eyring_t60_s[b], 1.0, b == 0 || b == 8 ? 0.15 : 0.05)
        << rsao.late.bands[b].center_hz << " Hz: " << rsao.late.bands[b].t60_s << " vs " << room.result.eyring_t60_s[b];
  }
  EXPECT_TRUE(rsao.warnings.empty()) << rsao.warnings.front();
}

TEST(RsaoEstimator, FumaInputGivesTheSameObjectAsAmbix) {
  const AudioBuffer& ambix = syntheticRoom().result.impulse_response;
  const Rsao from_ambix = estimateRsao(ambix, AmbisonicFormat::kAmbiX);
  const Rsao from_fuma = estimateRsao(ambixToFuma(ambix), AmbisonicFormat::kFuMa);
  ASSERT_EQ(from_ambix.reflections.size(), from_fuma.reflections.size());
  for (std::size_t k = 0; k < from_ambix.reflections.size(); ++k) {
    EXPECT_NEAR(from_fuma.reflections[k].time_of_arrival_s, from_ambix.reflections[k].time_of_arrival_s, 1e-7);
    EXPECT_NEAR(from_fuma.reflections[k].azimuth_rad, from_ambix.reflections[k].azimuth_rad, 1e-4);
    EXPECT_NEAR(from_fuma.reflections[k].level / from_ambix.reflections[k].level, 1.0, 1e-4);
  }
  EXPECT_NEAR(from_fuma.late.mixing_time_s, from_ambix.late.mixing_time_s, 1e-6);
}

TEST(RsaoEstimator, StatedFormatContradictedByTheChannelsIsAWarning) {
  const Rsao rsao = estimateRsao(syntheticRoom().result.impulse_response, AmbisonicFormat::kFuMa);
  ASSERT_FALSE(rsao.warnings.empty());
  EXPECT_NE(rsao.warnings.front().find("check the file's convention"), std::string::npos) << rsao.warnings.front();
}

TEST(RsaoEstimator, OtherSampleRatesAreResampledWithANote) {
  const AudioBuffer& ambix = syntheticRoom().result.impulse_response;
  const Rsao at48 = estimateRsao(ambix, AmbisonicFormat::kAmbiX);
  const Rsao at44 = estimateRsao(resample(ambix, 44100.0), AmbisonicFormat::kAmbiX);
  EXPECT_EQ(at44.sample_rate_hz, 48000.0);
  EXPECT_NEAR(at44.reflections[0].time_of_arrival_s, at48.reflections[0].time_of_arrival_s, 2e-5);
  EXPECT_NEAR(at44.reflections[0].azimuth_rad, at48.reflections[0].azimuth_rad, 0.02);
  bool noted = false;
  for (const auto& w : at44.warnings) noted = noted || w.find("44100 Hz resampled") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(RsaoEstimator, FixedMixingTimeIsUsed) {
  RsaoOptions options;
  options.mixing_time_s = 0.07;
  const Rsao rsao = estimateRsao(syntheticRoom().result.impulse_response, AmbisonicFormat::kAmbiX, options);
  EXPECT_DOUBLE_EQ(rsao.late.mixing_time_s, 0.07);
  EXPECT_GT(rsao.reflections.back().time_of_arrival_s, 0.03);
}

// Real rooms: the estimate is stable, its direct sound comes first, and the resynthesis
// has the measured decay.
//
// Checked per octave band, 125 Hz - 8 kHz, where the RSAO flags the band reliable:
//   - T20 of the resynthesised W within 10 % of the measured W's (the figure);
//   - EDT within 15 %, where EDT measures reverberation at all: the figure in the
//     bands where the direct sound does not hold the first 10 dB of the decay by itself
//     (C80 < 10 dB; above that EDT is the slope of a step and reads 2 ms to 0.7 s on
//     neighbouring bands of one RIR). 63 Hz and 16 kHz are left to the plausibility check:
//     the measured T20 at 63 Hz comes from a handful of modes (10-20 % off on three of the
//     five rooms), and at 16 kHz the octave model carries the 8 kHz band's slower decay
//     across the crossover (see docs/rsao.md).
// Measured on the five files (scripts/room_reverb rsao F --resynthesis, then metrics):
// T20 within 10 % in all 35 band checks, 2.7 % off on average (3.6 % with one slope per
// band, ROOM_REVERB_ONE_SLOPE=1); EDT within 15 % in 28 of 33 (also with the paper's
// onsets, ROOM_REVERB_PAPER_ONSETS=1, or one slope; 29 with the paper's LPC fit of the whole
// window, ROOM_REVERB_PAPER_LPC=1, where the Tyndall Bruce monument's 125 Hz reads -14.9 %
// instead of -15.1 %). The misses are listed with their
// errors (known_edt_misses) so that a change that helps or hurts them shows: Dixon at
// 125 Hz (+30 %: the early low-frequency energy arrives in a few strong modes the noise
// model spreads out; St Andrew's at 125 Hz, +18 % with the paper's onsets, is within
// with the defaults), St Andrew's at 8 kHz (-36 %) and the Tyndall Bruce monument at
// 500 Hz and 1 kHz (-34 %, -44 %), whose measured EDT is longer than their T20: a strong
// late arrival the exponential late model cannot carry; its 125 Hz sits on the line.
TEST(RsaoEstimatorRealData, StableDirectSoundFirstAndResynthesisKeepsTheDecay) {
  // (file, band) -> the EDT error measured when this test was written.
  const bool one_slope = std::getenv("ROOM_REVERB_ONE_SLOPE") != nullptr;
  const bool paper_onsets = std::getenv("ROOM_REVERB_PAPER_ONSETS") != nullptr;
  const bool paper_lpc = std::getenv("ROOM_REVERB_PAPER_LPC") != nullptr;
  std::map<std::pair<std::string, int>, double> known_edt_misses = {
      {{"dixon_studio_theatre_r1.wav", 125}, +0.296}, {{"st_andrews_church.wav", 125}, +0.182},
      {{"st_andrews_church.wav", 8000}, -0.391},      {{"tyndall_bruce_monument.wav", 500}, -0.296},
      {{"tyndall_bruce_monument.wav", 1000}, -0.440}, {{"tyndall_bruce_monument.wav", 125}, -0.151}};
  // Terry's bent 125 and 250 Hz decays with matching pursuit's reflections and one slope.
  if (one_slope && !paper_onsets) {
    known_edt_misses[{"terrys_typing_room.wav", 125}] = +0.228;
    known_edt_misses[{"terrys_typing_room.wav", 250}] = +0.170;
  }
  int edt_checks = 0, edt_within = 0, t20_checks = 0;
  double t20_error_sum = 0.0;
  for (const MeasuredCase& c : measuredCases()) {
    SCOPED_TRACE(c.file);
    const AudioBuffer rir = measured(c);
    RsaoOptions rsao_options;
    // The same checks with the paper's group-delay onsets (early_reflections.h).
    if (paper_onsets) rsao_options.early.onset_method = OnsetMethod::kGroupDelay;
    // ... and with the paper's one slope per band (late_reverb.h).
    if (one_slope) rsao_options.late.two_slopes = false;
    // ... and with the paper's LPC fit of the whole window (early_reflections.h).
    if (paper_lpc) rsao_options.early.lpc_flat_below_hz = 0.0;
    const Rsao rsao = estimateRsao(rir, c.format, rsao_options);
    const Rsao again = estimateRsao(rir, c.format, rsao_options);
    ASSERT_EQ(rsao.reflections.size(), again.reflections.size());
    for (std::size_t k = 0; k < rsao.reflections.size(); ++k) {
      EXPECT_EQ(rsao.reflections[k].time_of_arrival_s, again.reflections[k].time_of_arrival_s);
      EXPECT_EQ(rsao.reflections[k].level, again.reflections[k].level);
      EXPECT_EQ(rsao.reflections[k].azimuth_rad, again.reflections[k].azimuth_rad);
    }
    for (std::size_t b = 0; b < rsao.late.bands.size(); ++b) {
      EXPECT_EQ(rsao.late.bands[b].t60_s, again.late.bands[b].t60_s);
      EXPECT_EQ(rsao.late.bands[b].level, again.late.bands[b].level);
      EXPECT_EQ(rsao.late.bands[b].onset_level, again.late.bands[b].onset_level);
    }
    ASSERT_GE(rsao.reflections.size(), 2u);
    for (std::size_t k = 1; k < rsao.reflections.size(); ++k) {
      EXPECT_GT(rsao.reflections[k].time_of_arrival_s, rsao.reflections[0].time_of_arrival_s);
    }
    EXPECT_TRUE(rsao.warnings.empty()) << rsao.warnings.front();

    ResynthesisOptions options;
    options.duration_s = rir.durationS();
    const MetricsReport measured_metrics = analyseImpulseResponse(toAmbix(rir, c.format), 0, {});
    const MetricsReport resynthesis_metrics = analyseImpulseResponse(resynthesizeRsao(rsao, options), 0, {});
    for (std::size_t b = 1; b + 1 < rsao.late.bands.size(); ++b) {
      const double hz = rsao.late.bands[b].center_hz;
      SCOPED_TRACE(std::to_string(static_cast<int>(hz)) + " Hz");
      if (!rsao.late.bands[b].reliable) continue;
      const AcousticParameters& m = measured_metrics.bands[b];
      const AcousticParameters& r = resynthesis_metrics.bands[b];
      ASSERT_TRUE(m.t20_s && r.t20_s);
      EXPECT_NEAR(*r.t20_s / *m.t20_s, 1.0, 0.10) << *r.t20_s << " vs " << *m.t20_s;
      t20_error_sum += std::abs(*r.t20_s / *m.t20_s - 1.0);
      ++t20_checks;
      if (!(m.edt_s && r.edt_s && m.c80_db && *m.c80_db < 10.0)) continue;
      const double ratio = *r.edt_s / *m.edt_s;
      if (std::getenv("ROOM_REVERB_PRINT_DECAYS")) {
        std::printf("%-32s %5.0f Hz  T20 %+6.1f %%  EDT %+6.1f %%  slopes %d\n", c.file, hz,
                    100.0 * (*r.t20_s / *m.t20_s - 1.0), 100.0 * (ratio - 1.0), rsao.late.bands[b].second_share > 0.0 ? 2 : 1);
      }
      ++edt_checks;
      if (std::abs(ratio - 1.0) <= 0.15) {
        ++edt_within;
        continue;
      }
      // A known miss keeps its measured error, within 10 points either way.
      const auto miss = known_edt_misses.find({c.file, static_cast<int>(hz)});
      if (miss == known_edt_misses.end()) {
        ADD_FAILURE() << "EDT " << *r.edt_s << " vs " << *m.edt_s << " (" << 100.0 * (ratio - 1.0) << " %)";
        continue;
      }
      EXPECT_NEAR(ratio - 1.0, miss->second, 0.10) << "EDT " << *r.edt_s << " vs " << *m.edt_s;
    }
  }
  std::printf("[ measured ] T20 error mean %.2f %% over %d bands; EDT within 15 %% in %d of %d\n",
              100.0 * t20_error_sum / std::max(t20_checks, 1), t20_checks, edt_within, edt_checks);
  EXPECT_EQ(edt_checks, 33);
  // Matching pursuit and two slopes: 28 of 33 (Terry's 125 Hz EDT, bent, fits with two
  // slopes); the paper's onsets or one slope: 28; with the paper's LPC fit 29.
  EXPECT_GE(edt_within, paper_lpc && !paper_onsets && !one_slope ? 29 : one_slope && !paper_onsets ? 27 : 28);
  // The mean T20 error: 2.6 % with two slopes where the decay bends, 3.7 % with one.
  ASSERT_EQ(t20_checks, 35);
  EXPECT_LT(t20_error_sum / t20_checks, one_slope ? 0.04 : 0.03);
}

// ---------------------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------------------

TEST(RsaoEstimatorBadInput, WrongChannelCount) {
  const AudioBuffer omni = makeSilentBuffer(1, 48000, 48000.0);
  expectInputError([&] { estimateRsao(omni, AmbisonicFormat::kAmbiX); }, {"4 channels", "got 1"});
  const AudioBuffer five = makeSilentBuffer(5, 48000, 48000.0);
  expectInputError([&] { estimateRsao(five, AmbisonicFormat::kFuMa); }, {"4 channels", "got 5"});
}

TEST(RsaoEstimatorBadInput, HigherOrderAmbixUsesItsFirstOrder) {
  AudioBuffer third = syntheticRoom().result.impulse_response;
  for (std::size_t c = 4; c < 16; ++c) third.channels.push_back(std::vector<float>(third.frameCount(), 0.0f));
  const Rsao rsao = estimateRsao(third, AmbisonicFormat::kAmbiX);
  const Rsao first = estimateRsao(syntheticRoom().result.impulse_response, AmbisonicFormat::kAmbiX);
  EXPECT_EQ(rsao.reflections[0].time_of_arrival_s, first.reflections[0].time_of_arrival_s);
}

TEST(RsaoEstimatorBadInput, Silence) {
  const AudioBuffer silent = makeSilentBuffer(4, 48000, 48000.0);
  expectInputError([&] { estimateRsao(silent, AmbisonicFormat::kAmbiX); }, {"silent"});
}

TEST(RsaoEstimatorBadInput, NanSamples) {
  AudioBuffer rir = syntheticRoom().result.impulse_response;
  rir.channels[2][1000] = std::nanf("");
  expectInputError([&] { estimateRsao(rir, AmbisonicFormat::kAmbiX); }, {"NaN"});
}

TEST(RsaoEstimatorBadInput, NoClearDirectSound) {
  // Decaying noise with no direct sound: a reverberant tail and nothing to anchor it.
  AudioBuffer rir = makeSilentBuffer(4, 48000, 48000.0);
  for (std::size_t c = 0; c < 4; ++c) {
    rir.channels[c] = room_reverb::test::exponentialDecayNoise(48000, 0.8, 2400, 7 + static_cast<std::uint32_t>(c));
  }
  expectInputError([&] { estimateRsao(rir, AmbisonicFormat::kAmbiX); }, {"no clear direct sound"});
}

TEST(RsaoEstimatorBadInput, TooShort) {
  AudioBuffer rir = syntheticRoom().result.impulse_response;
  for (auto& channel : rir.channels) channel.resize(4800);  // 100 ms
  expectInputError([&] { estimateRsao(rir, AmbisonicFormat::kAmbiX); }, {"too short", "after the mixing time"});
}

TEST(RsaoEstimatorBadInput, ClippedInputIsFlagged) {
  AudioBuffer rir = syntheticRoom().result.impulse_response;
  // Driven 6 dB into the converter's limit: every sample above half the peak is cut flat.
  // The synthetic direct sound is a 2-sample pulse, so its neighbours are raised to the
  // limit too, as a real loudspeaker's wider pulse would be.
  auto& w = rir.channels[0];
  const auto at_peak = static_cast<std::size_t>(
      std::max_element(w.begin(), w.end(), [](float a, float b) { return std::abs(a) < std::abs(b); }) - w.begin());
  const float ceiling = 0.5f * std::abs(w[at_peak]);
  for (std::size_t n = at_peak - 2; n <= at_peak + 2; ++n) w[n] = std::copysign(ceiling, w[at_peak]);
  for (auto& channel : rir.channels) {
    for (float& v : channel) v = std::clamp(v, -ceiling, ceiling);
  }
  std::size_t at_ceiling = 0;
  for (float v : rir.channels[0]) at_ceiling += std::abs(v) == ceiling;
  ASSERT_GE(at_ceiling, 3u) << "the test signal must have a flat top";
  const Rsao rsao = estimateRsao(rir, AmbisonicFormat::kAmbiX);
  bool flagged = false;
  for (const auto& w : rsao.warnings) flagged = flagged || w.find("clipped") != std::string::npos;
  EXPECT_TRUE(flagged);
}

TEST(RsaoEstimatorBadInput, BadOptions) {
  RsaoOptions options;
  options.mixing_time_s = -1.0;
  expectInputError([&] { estimateRsao(syntheticRoom().result.impulse_response, AmbisonicFormat::kAmbiX, options); },
                   {"mixing_time_s"});
  options = {};
  options.early.lpc_order = 0;
  expectInputError([&] { estimateRsao(syntheticRoom().result.impulse_response, AmbisonicFormat::kAmbiX, options); },
                   {"lpc_order"});
  for (const double hz : {-1.0, 24000.0, std::nan("")}) {
    options = {};
    options.early.lpc_flat_below_hz = hz;
    expectInputError([&] { estimateRsao(syntheticRoom().result.impulse_response, AmbisonicFormat::kAmbiX, options); },
                     {"lpc_flat_below_hz"});
  }
}
