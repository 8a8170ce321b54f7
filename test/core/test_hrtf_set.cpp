#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "room_reverb/audio/fft.h"
#include "room_reverb/binaural/diffuse_field.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/common/error.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

const std::string kKu100 = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/hrtf/FHK_HRIR_L2354.sofa";
const std::string kMitKemar = "/usr/share/libmysofa/MIT_KEMAR_normal_pinna.sofa";

// Loaded once for the whole file: it takes a fifth of a second.
const HrtfSet& ku100() {
  static const HrtfSet set = HrtfSet::loadSofa(kKu100);
  return set;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Eigen::Vector3d horizontal(double azimuth_deg) {
  const double a = azimuth_deg * M_PI / 180.0;
  return {std::cos(a), std::sin(a), 0.0};
}

// Energy of `ir` between lower_hz and upper_hz.
double bandEnergy(const std::vector<float>& ir, double rate_hz, double lower_hz, double upper_hz) {
  RealFft fft(nextFastFftSize(ir.size()));
  std::vector<float> padded(fft.size(), 0.0f);
  std::copy(ir.begin(), ir.end(), padded.begin());
  const std::vector<std::complex<float>> spectrum = fft.forward(padded);
  double energy = 0.0;
  for (std::size_t k = 0; k < spectrum.size(); ++k) {
    const double f = static_cast<double>(k) * rate_hz / static_cast<double>(fft.size());
    if (f >= lower_hz && f <= upper_hz) energy += std::norm(spectrum[k]);
  }
  return energy;
}

double ildDb(const HrtfSet& set, std::size_t i) {
  const double rate = set.sampleRateHz();
  return 10.0 * std::log10(bandEnergy(set.hrir(i).left, rate, 1000.0, 4000.0) /
                           bandEnergy(set.hrir(i).right, rate, 1000.0, 4000.0));
}

// The whole-sample -20 dB onset, an estimate independent of the set's own.
std::size_t coarseOnset(const std::vector<float>& ir) {
  float peak = 0.0f;
  for (float v : ir) peak = std::max(peak, std::abs(v));
  std::size_t n = 0;
  while (std::abs(ir[n]) < 0.1f * peak) ++n;
  return n;
}

// The onsets of an arbitrary HRIR, as the set estimates them for measured ones.
HrirOnset onsetOf(const Hrir& hrir, double rate_hz) {
  return HrtfSet(rate_hz, {Eigen::Vector3d::UnitX()}, {hrir}).onset(0);
}

float maxAbsDifference(const std::vector<float>& a, const std::vector<float>& b) {
  float worst = 0.0f;
  for (std::size_t n = 0; n < a.size(); ++n) worst = std::max(worst, std::abs(a[n] - b[n]));
  return worst;
}

// Roughly even directions on the sphere (a Fibonacci spiral).
std::vector<Eigen::Vector3d> spiralDirections(std::size_t count) {
  std::vector<Eigen::Vector3d> directions;
  for (std::size_t i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(count);
    const double azimuth = static_cast<double>(i) * M_PI * (3.0 - std::sqrt(5.0));
    const double r = std::sqrt(1.0 - z * z);
    directions.emplace_back(r * std::cos(azimuth), r * std::sin(azimuth), z);
  }
  return directions;
}

// A short smooth pulse (Hann-shaped) starting at `start`, in `length` samples.
std::vector<float> pulse(std::size_t length, std::size_t start) {
  std::vector<float> ir(length, 0.0f);
  for (std::size_t n = 0; n < 7; ++n) {
    ir[start + n] = static_cast<float>(0.5 - 0.5 * std::cos(2.0 * M_PI * (n + 1.0) / 8.0));
  }
  return ir;
}

}  // namespace

TEST(HrtfSet, LoadsTheKu100Set) {
  const HrtfSet& set = ku100();
  EXPECT_EQ(set.size(), 2354u);
  EXPECT_EQ(set.sampleRateHz(), 48000.0);
  EXPECT_EQ(set.length(), 128u);
  for (std::size_t i = 0; i < set.size(); ++i) {
    ASSERT_NEAR(set.direction(i).norm(), 1.0, 1e-12) << i;
    ASSERT_EQ(set.hrir(i).left.size(), 128u);
    ASSERT_EQ(set.hrir(i).right.size(), 128u);
  }
  EXPECT_NE(set.description().find("HRIR_L2354"), std::string::npos) << set.description();
  for (const std::string& note : set.notes()) EXPECT_EQ(note.find("resampled"), std::string::npos);
}

TEST(HrtfSet, SourceOnTheLeftIsLouderAtTheLeftEar) {
  const HrtfSet& set = ku100();
  const std::size_t left = set.nearest(horizontal(90.0));
  const std::size_t right = set.nearest(horizontal(-90.0));
  ASSERT_GT(set.direction(left).y(), 0.999);
  ASSERT_LT(set.direction(right).y(), -0.999);
  // Measured: +6.7 dB and -6.9 dB over 1-4 kHz (less than further up: right behind the
  // head, waves from both sides meet in phase, the "bright spot" of a sphere).
  EXPECT_GT(ildDb(set, left), 4.0);
  EXPECT_LT(ildDb(set, left), 20.0);
  EXPECT_LT(ildDb(set, right), -4.0);
  EXPECT_GT(ildDb(set, right), -20.0);
  EXPECT_NEAR(ildDb(set, set.nearest(horizontal(0.0))), 0.0, 2.0);
}

TEST(HrtfSet, InterauralDelayAtNinetyDegreesHasTheLeftEarLeading) {
  const HrtfSet& set = ku100();
  const std::size_t i = set.nearest(horizontal(90.0));
  const HrirOnset& onset = set.onset(i);
  const double itd_ms = (onset.right - onset.left) / set.sampleRateHz() * 1e3;
  EXPECT_GT(itd_ms, 0.6);  // measured 0.683 ms
  EXPECT_LT(itd_ms, 0.8);
  // The sub-sample onsets agree with a plain whole-sample threshold.
  EXPECT_NEAR(onset.left, static_cast<double>(coarseOnset(set.hrir(i).left)), 1.0);
  EXPECT_NEAR(onset.right, static_cast<double>(coarseOnset(set.hrir(i).right)), 1.0);
}

TEST(HrtfSet, NearestFindsEveryMeasuredDirection) {
  const HrtfSet& set = ku100();
  for (std::size_t i = 0; i < set.size(); ++i) {
    ASSERT_EQ(set.nearest(set.direction(i)), i);
    ASSERT_EQ(set.nearest(3.0 * set.direction(i)), i);  // the length does not matter
  }
}

TEST(HrtfSet, InterpolationAtAMeasuredDirectionGivesItsHrir) {
  const HrtfSet& set = ku100();
  for (std::size_t i = 0; i < set.size(); i += 37) {
    const Hrir h = set.interpolated(set.direction(i));
    ASSERT_LT(maxAbsDifference(h.left, set.hrir(i).left), 1e-5f) << i;
    ASSERT_LT(maxAbsDifference(h.right, set.hrir(i).right), 1e-5f) << i;
  }
  // And it is continuous there: 0.001 deg away the measured HRIR still dominates.
  const std::size_t i = set.nearest(horizontal(30.0));
  const Eigen::Vector3d& d = set.direction(i);
  const Eigen::Vector3d nudged = (d + 1.7e-5 * Eigen::Vector3d(-d.y(), d.x(), 0.0)).normalized();
  const Hrir h = set.interpolated(nudged);
  float peak = 0.0f;
  for (float v : set.hrir(i).left) peak = std::max(peak, std::abs(v));
  EXPECT_LT(maxAbsDifference(h.left, set.hrir(i).left), 0.01f * peak);
}

TEST(HrtfSet, InterpolationMidwayPutsTheOnsetBetweenTheNeighbours) {
  const HrtfSet& set = ku100();
  // Two neighbours on the horizontal plane where the ITD changes fast.
  const std::size_t a = set.nearest(horizontal(45.0));
  std::size_t b = a;
  double best = -2.0;
  for (std::size_t j = 0; j < set.size(); ++j) {
    const double dot = set.direction(j).dot(set.direction(a));
    if (j != a && std::abs(set.direction(j).z()) < 1e-6 && set.direction(j).y() > set.direction(a).y() && dot > best) {
      best = dot;
      b = j;
    }
  }
  ASSERT_NE(a, b);
  const Eigen::Vector3d midway = (set.direction(a) + set.direction(b)).normalized();
  const Hrir h = set.interpolated(midway);
  const HrirOnset mid = onsetOf(h, set.sampleRateHz());
  const HrirOnset& oa = set.onset(a);
  const HrirOnset& ob = set.onset(b);
  const double tolerance = 0.05;  // samples
  EXPECT_GT(mid.left, std::min(oa.left, ob.left) - tolerance);
  EXPECT_LT(mid.left, std::max(oa.left, ob.left) + tolerance);
  EXPECT_GT(mid.right, std::min(oa.right, ob.right) - tolerance);
  EXPECT_LT(mid.right, std::max(oa.right, ob.right) + tolerance);
  // The level lies between the neighbours' too (no comb-filter loss).
  const double rate = set.sampleRateHz();
  const double ea = bandEnergy(set.hrir(a).right, rate, 1000.0, 8000.0);
  const double eb = bandEnergy(set.hrir(b).right, rate, 1000.0, 8000.0);
  const double em = bandEnergy(h.right, rate, 1000.0, 8000.0);
  EXPECT_GT(em, 0.8 * std::min(ea, eb));
  EXPECT_LT(em, 1.25 * std::max(ea, eb));
}

TEST(HrtfSet, InterpolationAlignsDelaysInsteadOfAveragingThem) {
  // Two directions whose HRIRs are the same pulse, 4 samples apart: halfway, a time-aligned
  // interpolation gives one pulse 2 samples from each, not two half pulses.
  const std::size_t length = 64;
  const HrtfSet set(48000.0, {horizontal(0.0), horizontal(10.0)},
                    {{pulse(length, 10), pulse(length, 20)}, {pulse(length, 14), pulse(length, 16)}});
  const Hrir h = set.interpolated(horizontal(5.0));
  EXPECT_LT(maxAbsDifference(h.left, pulse(length, 12)), 1e-4f);
  EXPECT_LT(maxAbsDifference(h.right, pulse(length, 18)), 1e-4f);
}

TEST(HrtfSet, OtherRatesAreResampledWithANote) {
  if (!std::filesystem::exists(kMitKemar)) GTEST_SKIP() << kMitKemar << " is not installed";
  const HrtfSet set = HrtfSet::loadSofa(kMitKemar, 48000.0);
  EXPECT_EQ(set.sampleRateHz(), 48000.0);
  EXPECT_EQ(set.size(), 710u);
  EXPECT_EQ(set.length(), 557u);  // 512 taps at 44.1 kHz
  const auto& notes = set.notes();
  EXPECT_TRUE(std::any_of(notes.begin(), notes.end(), [](const std::string& note) {
    return note.find("resampled from 44100 Hz to 48000 Hz") != std::string::npos;
  }));
  EXPECT_GT(ildDb(set, set.nearest(horizontal(90.0))), 4.0);  // measured 8.0 dB
}

TEST(HrtfSet, BadFilesAreClearErrors) {
  expectInputError([] { HrtfSet::loadSofa("/no/such/hrtf.sofa"); }, {"/no/such/hrtf.sofa", "no such file"});
  std::string garbage;
  for (int i = 0; i < 4000; ++i) garbage.push_back(static_cast<char>((i * 7919) % 251));
  const std::string garbage_path = room_reverb::test::writeFile("garbage.sofa", garbage);
  expectInputError([&] { HrtfSet::loadSofa(garbage_path); }, {"garbage.sofa", "not a readable SOFA file"});

  const std::string bytes = readBytes(kKu100);
  ASSERT_GT(bytes.size(), 1000000u);
  const std::string truncated = room_reverb::test::writeFile("truncated.sofa", bytes.substr(0, bytes.size() / 2));
  expectInputError([&] { HrtfSet::loadSofa(truncated); }, {"truncated.sofa", "not a readable SOFA file"});

  std::string other = bytes;
  const std::size_t at = other.find("SimpleFreeFieldHRIR");
  ASSERT_NE(at, std::string::npos);
  other.replace(at, 19, "SimpleFreeFieldHRTF");
  const std::string other_path = room_reverb::test::writeFile("hrtf_convention.sofa", other);
  expectInputError([&] { HrtfSet::loadSofa(other_path); }, {"SimpleFreeFieldHRTF", "only SimpleFreeFieldHRIR"});
}

TEST(HrtfSet, InconsistentSetsInMemoryAreClearErrors) {
  const Hrir ok{std::vector<float>(8, 0.1f), std::vector<float>(8, 0.1f)};
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  expectInputError([&] { HrtfSet(48000.0, {}, {}); }, {"empty"});
  expectInputError([&] { HrtfSet(48000.0, {x, x}, {ok}); }, {"2 directions but 1 HRIRs"});
  expectInputError([&] { HrtfSet(48000.0, {x, x}, {ok, {std::vector<float>(8), std::vector<float>(9)}}); },
                   {"direction 1", "same length"});
  Hrir nan = ok;
  nan.right[3] = std::numeric_limits<float>::quiet_NaN();
  expectInputError([&] { HrtfSet(48000.0, {x}, {nan}, "test set"); }, {"'test set'", "NaN"});
  expectInputError([&] { HrtfSet(48000.0, {Eigen::Vector3d::Zero()}, {ok}); }, {"zero"});
  expectInputError([&] { HrtfSet(0.0, {x}, {ok}); }, {"sample rate"});
  expectInputError([&] { ku100().interpolated(Eigen::Vector3d::Zero()); }, {"interpolate", "zero"});
  expectInputError([&] { ku100().nearest(Eigen::Vector3d(NAN, 0.0, 1.0)); }, {"nearest", "non-finite"});
}

TEST(DiffuseField, Ku100CoherenceFallsFromOneToZero) {
  const std::vector<double> centres{63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000};
  const DiffuseFieldSpectrum spectrum = diffuseFieldSpectrum(ku100());
  const std::vector<double> coherence = diffuseFieldCoherence(spectrum, centres);
  ASSERT_EQ(coherence.size(), centres.size());
  // Measured: 0.970 0.891 0.583 0.022 -0.009 -0.003 0.009 0.006 -0.003. The ears are
  // 18 cm apart plus the way round the head: coherent well below 500 Hz, not above.
  EXPECT_GT(coherence[0], 0.95);
  EXPECT_GT(coherence[1], 0.85);
  EXPECT_GT(coherence[2], 0.45);
  EXPECT_LT(coherence[2], 0.75);
  for (std::size_t b = 3; b < centres.size(); ++b) EXPECT_LT(std::abs(coherence[b]), 0.1) << centres[b];

  EXPECT_LE(spectrum.bin_spacing_hz, 12.0);
  for (std::size_t k = 0; k < spectrum.coherence.size(); ++k) {
    ASSERT_LE(std::abs(spectrum.coherence[k]), 1.0 + 1e-9);
    ASSERT_GE(spectrum.power_left[k], 0.0);
  }
}

TEST(DiffuseField, IdenticalEarsAreFullyCoherent) {
  const std::vector<Eigen::Vector3d> directions = spiralDirections(100);
  std::vector<Hrir> hrirs;
  for (std::size_t i = 0; i < directions.size(); ++i) {
    std::vector<float> ir(32, 0.0f);
    for (std::size_t n = 0; n < ir.size(); ++n) ir[n] = static_cast<float>(std::sin(0.7 * (n + 1) * (i + 1)) * std::exp(-0.2 * n));
    hrirs.push_back({ir, ir});
  }
  const HrtfSet set(48000.0, directions, hrirs);
  for (double c : diffuseFieldCoherence(set, {63, 125, 1000, 8000, 16000})) EXPECT_NEAR(c, 1.0, 1e-9);
  expectInputError([&] { diffuseFieldCoherence(set, {0.0}); }, {"not a positive frequency"});
  expectInputError([&] { diffuseFieldCoherence(set, {100000.0}); }, {"holds no frequency"});
}
