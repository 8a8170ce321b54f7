// The catalogue's `measurement_limits`: a limit of the measurement is flagged as the
// measurement's and never fitted. Planted in otherwise clean B-format responses (a direct
// sound and a diffuse exponential tail, T60 0.5 s): a clipped file, a noise floor 25 dB
// down, and an AmbiX file declared FuMa. Each is flagged with its issue on its own pair,
// and the clean pair is not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "room_reverb/audio/audio_file.h"
#include "room_reverb/evaluation/measured_evidence.h"
#include "synthetic_rir.h"
#include "test_files.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

constexpr std::size_t kOnset = 2400;  // 50 ms
constexpr double kT60 = 0.5;

// First-order AmbiX (SN3D): a direct sound from +x and a diffuse tail whose three
// directional channels each carry a third of W's energy.
AudioBuffer cleanAmbix(std::uint32_t seed) {
  const std::size_t n = static_cast<std::size_t>(1.2 * kFs);
  AudioBuffer b;
  b.sample_rate_hz = kFs;
  b.channels.push_back(exponentialDecayNoise(n, kT60, kOnset + 240, seed));
  for (std::uint32_t c = 1; c < 4; ++c) {
    std::vector<float> x = exponentialDecayNoise(n, kT60, kOnset + 240, seed + 10 * c);
    for (float& v : x) v /= static_cast<float>(std::sqrt(3.0));
    b.channels.push_back(x);
  }
  // The direct sound from +x: a 9-sample Hann pulse, as a loudspeaker's band limits make it.
  for (std::size_t k = 0; k < 9; ++k) {
    const float direct = static_cast<float>(20.0 * std::pow(std::sin(M_PI * (k + 1) / 10.0), 2));
    b.channels[0][kOnset + k] += direct;
    b.channels[3][kOnset + k] += direct;
  }
  // Full scale well above every sample, so that only the planted clipping clips (the
  // direct sound's peak at 0.5).
  float peak = 0.0f;
  for (const auto& ch : b.channels) for (float v : ch) peak = std::max(peak, std::abs(v));
  for (auto& ch : b.channels) for (float& v : ch) v *= 0.5f / peak;
  return b;
}

MeasurementPair pairFor(const std::string& name, const AudioBuffer& b, const std::string& format) {
  MeasurementPair p;
  p.label = name;
  p.file = tempPath(name + ".wav").string();
  p.format = format;
  p.source_m = {1.0, 1.0, 1.5};
  p.receiver_m = {3.0, 2.0, 1.5};
  writeAudioFile(p.file, b, SampleEncoding::kFloat32);
  return p;
}

std::vector<std::string> issuesOf(const MeasuredEvidence& e, const std::string& pair) {
  std::vector<std::string> issues;
  for (const MeasurementFlag& f : e.flags) {
    if (f.pair == pair) issues.push_back(f.issue);
  }
  return issues;
}

TEST(MeasurementLimits, EachPlantedLimitIsFlaggedOnItsOwnPair) {
  Measurements m;
  m.pairs.push_back(pairFor("clean", cleanAmbix(1), "ambix"));

  AudioBuffer clipped = cleanAmbix(2);
  for (auto& ch : clipped.channels) {
    for (float& v : ch) v = std::clamp(v * 4.0f, -0.6f, 0.6f);  // 12 dB too hot: the direct sound's top cut flat
  }
  m.pairs.push_back(pairFor("clipped", clipped, "ambix"));

  AudioBuffer noisy = cleanAmbix(3);
  for (std::size_t c = 0; c < 4; ++c) {
    std::vector<float> floor = whiteNoise(noisy.channels[c].size(), 40 + static_cast<std::uint32_t>(c));
    // 25 dB below the tail's start (less than the 35 dB, 5 + 30, that T20 needs), and
    // isotropic like the tail (a third of W's energy in each directional channel), so that
    // it limits the decay range and nothing else.
    const double tail_rms = 0.5 / 20.0;  // the scaling above made the direct 0.5 and the tail's start 1/20 of it
    const double level = tail_rms * std::pow(10.0, -25.0 / 20.0) / (c == 0 ? 1.0 : std::sqrt(3.0));
    for (std::size_t i = 0; i < floor.size(); ++i) noisy.channels[c][i] += static_cast<float>(level) * floor[i];
  }
  m.pairs.push_back(pairFor("noisy", noisy, "ambix"));

  m.pairs.push_back(pairFor("mislabelled", cleanAmbix(4), "fuma"));

  const MeasuredEvidence e = measuredEvidence(m);
  std::string all;
  for (const MeasurementFlag& f : e.flags) all += f.pair + ": " + f.issue + " (" + f.detail + ")\n";
  EXPECT_TRUE(issuesOf(e, "clean").empty()) << all;
  EXPECT_EQ(issuesOf(e, "clipped"), std::vector<std::string>{"clipping"}) << all;
  const std::vector<std::string> noisy_issues = issuesOf(e, "noisy");
  EXPECT_NE(std::find(noisy_issues.begin(), noisy_issues.end(), "noise_floor"), noisy_issues.end()) << all;
  EXPECT_EQ(std::count(noisy_issues.begin(), noisy_issues.end(), "clipping"), 0);
  EXPECT_EQ(issuesOf(e, "mislabelled"), std::vector<std::string>{"bformat_convention"}) << all;
  // Every flag says what it means for the comparison.
  for (const MeasurementFlag& f : e.flags) EXPECT_FALSE(f.detail.empty()) << f.pair << " " << f.issue;
}

}  // namespace
}  // namespace room_reverb::test
