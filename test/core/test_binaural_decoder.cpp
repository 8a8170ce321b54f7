// Ambisonic-to-binaural decoders against known truth: a spherical head model (Brown & Duda
// 1998) whose HRIRs exist for every direction, and the measured KU100 set. A plane wave
// encoded at a direction and decoded must reach the ears with the interaural cues of that
// direction's HRIR.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/binaural/binaural_cues.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/decoder_comparison.h"
#include "room_reverb/binaural/loudspeaker_layout.h"
#include "room_reverb/common/error.h"
#include "spherical_head.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d direction(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * kPi / 180.0, el = elevation_deg * kPi / 180.0;
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

// The octave bands 500 Hz .. 8 kHz, where the ILD is compared.
std::vector<FrequencyBand> ildBands() {
  std::vector<FrequencyBand> bands;
  for (const auto& band : standardBands(BandResolution::kOctave)) {
    if (band.nominal_hz >= 500.0 && band.nominal_hz <= 8000.0) bands.push_back(band);
  }
  return bands;
}

// A unit impulse arriving as a plane wave from `from`, encoded as AmbiX of `order`.
AudioBuffer encodedImpulse(int order, const Eigen::Vector3d& from) {
  const std::vector<double> harmonics = sn3dHarmonics(order, from);
  AudioBuffer ambix = makeSilentBuffer(harmonics.size(), 1, 48000.0);
  for (std::size_t c = 0; c < harmonics.size(); ++c) ambix.channels[c][0] = static_cast<float>(harmonics[c]);
  return ambix;
}

Hrir decodeImpulse(const BinauralDecoder& decoder, const Eigen::Vector3d& from) {
  const AudioBuffer binaural = decodeToBinaural(encodedImpulse(decoder.order, from), decoder);
  return {binaural.channels[0], binaural.channels[1]};
}

// Expects the decoded plane wave's ILDs (per octave band 500 Hz .. 8 kHz, one tolerance
// per band) and low-frequency ITD to match the direct HRIR's.
void expectSameCues(const Hrir& decoded, const Hrir& direct, const std::vector<double>& ild_tolerance_db,
                    double itd_tolerance_us, const std::string& where) {
  const auto bands = ildBands();
  const auto ild_decoded = interauralLevelDifferencesDb(decoded, 48000.0, bands);
  const auto ild_direct = interauralLevelDifferencesDb(direct, 48000.0, bands);
  for (std::size_t b = 0; b < bands.size(); ++b) {
    EXPECT_NEAR(ild_decoded[b], ild_direct[b], ild_tolerance_db.at(b)) << where << ", " << bands[b].nominal_hz << " Hz";
  }
  EXPECT_NEAR(1e6 * interauralTimeDifferenceS(decoded, 48000.0), 1e6 * interauralTimeDifferenceS(direct, 48000.0),
              itd_tolerance_us)
      << where;
}

// Built once per test program: the decoders are what the tests share.
const HrtfSet& sphericalHead() {
  static const HrtfSet set = room_reverb::test::sphericalHeadHrtfSet(1000);
  return set;
}
const BinauralDecoder& sphericalHeadDecoder(int order) {
  static const std::vector<BinauralDecoder> decoders = {makeBinauralDecoder(sphericalHead(), 1),
                                                         makeBinauralDecoder(sphericalHead(), 2),
                                                         makeBinauralDecoder(sphericalHead(), 3)};
  return decoders.at(static_cast<std::size_t>(order - 1));
}

std::string kuPath() { return std::string(ROOM_REVERB_SOURCE_DIR) + "/data/hrtf/FHK_HRIR_L2354.sofa"; }
const HrtfSet& ku100() {
  static const HrtfSet set = HrtfSet::loadSofa(kuPath());
  return set;
}

}  // namespace

TEST(BinauralCues, ItdEstimatorFindsADelay) {
  Hrir pair = room_reverb::test::sphericalHeadHrir(direction(0.0, 0.0));
  const Hrir later = room_reverb::test::sphericalHeadHrir(direction(0.0, 0.0));
  // Front: both ears identical, so ITD 0; the same response shifted is a pure delay.
  EXPECT_NEAR(interauralTimeDifferenceS(pair, 48000.0), 0.0, 1e-6);
  pair.right.assign(pair.right.size(), 0.0f);
  for (std::size_t n = 13; n < pair.right.size(); ++n) pair.right[n] = later.left[n - 13];
  EXPECT_NEAR(interauralTimeDifferenceS(pair, 48000.0) * 48000.0, 13.0, 0.05);
  std::swap(pair.left, pair.right);
  EXPECT_NEAR(interauralTimeDifferenceS(pair, 48000.0) * 48000.0, -13.0, 0.05);
}

TEST(BinauralCues, SphericalHeadHasARigidSpheresLowFrequencyItd) {
  // The model's pure delays give Woodworth's (a/c)(pi/2 + 1) = 656 us at the side; the head
  // shadow's phase adds to it below 1.5 kHz, towards the rigid sphere's low-frequency
  // limit 3 (a/c) sin(theta) = 765 us (Kuhn, JASA 62(1), 1977).
  const Eigen::Vector3d side = direction(90.0, 0.0);
  const double itd = interauralTimeDifferenceS(room_reverb::test::sphericalHeadHrir(side), 48000.0);
  EXPECT_GT(itd, room_reverb::test::sphericalHeadItdS(side));
  EXPECT_NEAR(itd, 3.0 * room_reverb::test::kHeadRadiusM / room_reverb::test::kHeadSpeedOfSoundMS, 20e-6);
  EXPECT_GT(interauralLevelDifferencesDb(room_reverb::test::sphericalHeadHrir(side), 48000.0, ildBands()).back(), 10.0);
}

TEST(BinauralDecoder, PlaneWavesDecodeToTheHrirOfTheirDirection) {
  // Order 3 holds the field around the head up to k r = 3 (1.9 kHz): there the ILD is
  // within 1 dB everywhere. Above, MagLS fits magnitudes only and the ILD of a lateral
  // source errs by up to 3 dB (measured 2.8 dB in the 2 kHz band at the side, just above
  // the cutoff, where neither the complex nor the magnitude fit is good; 2.5 dB at 8 kHz).
  const std::vector<double> frontal = {1.0, 1.0, 1.5, 1.5, 2.5};
  const std::vector<double> lateral = {1.0, 1.0, 3.0, 1.0, 3.0};
  const BinauralDecoder& decoder = sphericalHeadDecoder(3);
  for (const auto& [az, el] : std::vector<std::pair<double, double>>{{90.0, 0.0}, {-90.0, 0.0}, {0.0, 0.0},
                                                                     {45.0, 0.0}, {-60.0, 20.0}, {150.0, -30.0},
                                                                     {-120.0, 45.0}, {30.0, -60.0}, {0.0, 60.0}}) {
    const Eigen::Vector3d d = direction(az, el);
    expectSameCues(decodeImpulse(decoder, d), room_reverb::test::sphericalHeadHrir(d),
                   std::abs(std::abs(az) - 90.0) < 1.0 ? lateral : frontal, 50.0,
                   "az " + std::to_string(az) + " el " + std::to_string(el));
  }
}

TEST(BinauralDecoder, VirtualLoudspeakerDecoderKeepsTheLowFrequencyItd) {
  const BinauralDecoder decoder =
      makeVirtualLoudspeakerDecoder(sphericalHead(), 3, loudspeakerLayoutByName(kDefaultLoudspeakerLayout));
  for (const double az : {90.0, 30.0, -135.0}) {
    const Eigen::Vector3d d = direction(az, 0.0);
    const Hrir decoded = decodeImpulse(decoder, d);
    EXPECT_NEAR(1e6 * interauralTimeDifferenceS(decoded, 48000.0),
                1e6 * interauralTimeDifferenceS(room_reverb::test::sphericalHeadHrir(d), 48000.0), 50.0)
        << "az " << az;
  }
}

TEST(BinauralDecoder, LeftRightAndFrontBackSymmetricForASymmetricHead) {
  const BinauralDecoder& decoder = sphericalHeadDecoder(3);
  const auto bands = ildBands();
  for (const auto& [az, el] : std::vector<std::pair<double, double>>{{60.0, 0.0}, {20.0, 30.0}, {75.0, -40.0}}) {
    const Hrir front_left = decodeImpulse(decoder, direction(az, el));
    const Hrir front_right = decodeImpulse(decoder, direction(-az, el));
    const Hrir back_left = decodeImpulse(decoder, direction(180.0 - az, el));
    const double itd = interauralTimeDifferenceS(front_left, 48000.0);
    EXPECT_NEAR(interauralTimeDifferenceS(front_right, 48000.0), -itd, 10e-6) << az << " " << el;
    EXPECT_NEAR(interauralTimeDifferenceS(back_left, 48000.0), itd, 10e-6) << az << " " << el;
    const auto ild = interauralLevelDifferencesDb(front_left, 48000.0, bands);
    const auto ild_mirrored = interauralLevelDifferencesDb(front_right, 48000.0, bands);
    const auto ild_back = interauralLevelDifferencesDb(back_left, 48000.0, bands);
    for (std::size_t b = 0; b < bands.size(); ++b) {
      EXPECT_NEAR(ild_mirrored[b], -ild[b], 0.5) << az << " " << el << " " << bands[b].nominal_hz;
      EXPECT_NEAR(ild_back[b], ild[b], 0.5) << az << " " << el << " " << bands[b].nominal_hz;
    }
  }
}

TEST(BinauralDecoder, HigherOrdersRenderTheCuesBetter) {
  const DecoderComparison first = compareDecoderToHrtf(sphericalHeadDecoder(1), sphericalHead(), 100);
  const DecoderComparison second = compareDecoderToHrtf(sphericalHeadDecoder(2), sphericalHead(), 100);
  const DecoderComparison third = compareDecoderToHrtf(sphericalHeadDecoder(3), sphericalHead(), 100);
  EXPECT_GT(first.itd_error_us, 2.0 * third.itd_error_us);
  EXPECT_GT(second.itd_error_us, third.itd_error_us);
  EXPECT_GT(first.ild_error_db_mean, third.ild_error_db_mean);
  // Over all directions order 3 is within 1 dB of ILD and 20 us of ITD on average
  // (measured 0.50 dB and 9 us).
  EXPECT_LT(third.ild_error_db_mean, 1.0);
  EXPECT_LT(third.itd_error_us, 20.0);
}

TEST(BinauralDecoder, MagLsBeatsLeastSquaresAtHighFrequenciesAndKeepsTheDiffuseField) {
  const BinauralDecoder least_squares = makeLeastSquaresDecoder(sphericalHead(), 3);
  const DecoderComparison ls = compareDecoderToHrtf(least_squares, sphericalHead(), 100);
  const DecoderComparison magls = compareDecoderToHrtf(sphericalHeadDecoder(3), sphericalHead(), 100);
  EXPECT_LT(magls.ild_error_db.back(), 0.5 * ls.ild_error_db.back());  // 8 kHz
  EXPECT_LT(magls.itd_error_us, ls.itd_error_us + 5.0);                // the same fit below the cutoff
  // The covariance constraint gives a diffuse field the HRTF set's ear powers and coherence.
  EXPECT_LT(magls.diffuse_level_error_db_mean, 0.2);
  EXPECT_LT(magls.diffuse_coherence_error_mean, 0.02);
  MagLsOptions unconstrained;
  unconstrained.diffuse_field_covariance = false;
  const DecoderComparison free =
      compareDecoderToHrtf(makeMagLsDecoder(sphericalHead(), 3, unconstrained), sphericalHead(), 100);
  EXPECT_GT(free.diffuse_coherence_error_mean, 2.0 * magls.diffuse_coherence_error_mean);
}

TEST(BinauralDecoder, OutputHasTwoChannelsOfSignalPlusFilterLength) {
  const BinauralDecoder& decoder = sphericalHeadDecoder(2);
  EXPECT_EQ(decoder.filters.size(), 9u);
  EXPECT_EQ(decoder.filters.front().left.size(), room_reverb::test::kSphericalHeadHrirLength + kDecoderFilterMargin);
  AudioBuffer ambix = makeSilentBuffer(9, 1000, 48000.0);
  const AudioBuffer binaural = decodeToBinaural(ambix, decoder);
  EXPECT_EQ(binaural.channelCount(), 2u);
  EXPECT_EQ(binaural.frameCount(), 1000u + decoder.filters.front().left.size() - 1);
  // decodedPlaneWaveResponse is what decoding an impulse gives.
  const Eigen::Vector3d d = direction(-30.0, 10.0);
  const Hrir by_buffer = decodeImpulse(decoder, d);
  const Hrir direct = decodedPlaneWaveResponse(decoder, d);
  for (std::size_t n = 0; n < direct.left.size(); ++n) EXPECT_NEAR(by_buffer.left[n], direct.left[n], 1e-5);
}

TEST(BinauralDecoder, RejectsBadInput) {
  const HrtfSet& head = sphericalHead();
  expectInputError([&] { makeMagLsDecoder(head, 0); }, {"order 0"});
  expectInputError([&] { makeLeastSquaresDecoder(head, 4); }, {"order 4"});
  expectInputError([&] { makeVirtualLoudspeakerDecoder(head, 4, fibonacciLayout(50)); }, {"order 4"});
  expectInputError([&] { makeVirtualLoudspeakerDecoder(head, 2, {}); }, {"empty"});
  expectInputError([&] { makeVirtualLoudspeakerDecoder(head, 3, fibonacciLayout(50), {true, true, 64}); },
                   {"shorter than the HRIRs"});
  expectInputError([&] { decodedPlaneWaveResponse(BinauralDecoder{}, direction(0.0, 0.0)); }, {"incomplete"});
}

TEST(BinauralDecoder, PaperRingsDecodeDespiteTheirEmptyPoles) {
  // Three elevations cannot carry four zonal harmonics at order 3: the pseudo-inverse drops
  // that combination instead of blowing it up, and the horizontal plane still decodes well.
  const BinauralDecoder decoder = makeVirtualLoudspeakerDecoder(sphericalHead(), 3, paperRingsLayout());
  const Eigen::Vector3d side = direction(90.0, 0.0);
  const Hrir decoded = decodeImpulse(decoder, side);
  for (const float x : decoded.left) ASSERT_TRUE(std::isfinite(x));
  EXPECT_NEAR(1e6 * interauralTimeDifferenceS(decoded, 48000.0),
              1e6 * interauralTimeDifferenceS(room_reverb::test::sphericalHeadHrir(side), 48000.0), 50.0);
}

TEST(BinauralDecoder, RejectsWrongChannelCountsAndRates) {
  const BinauralDecoder& decoder = sphericalHeadDecoder(3);
  expectInputError([&] { decodeToBinaural(makeSilentBuffer(4, 100, 48000.0), decoder); }, {"16", "4"});
  expectInputError([&] { decodeToBinaural(makeSilentBuffer(16, 100, 44100.0), decoder); }, {"resample"});
  expectInputError([&] { decodeToBinaural(makeSilentBuffer(16, 100, 48000.0), BinauralDecoder{}); }, {"incomplete"});
}

TEST(BinauralDecoder, ParsesMethodNames) {
  EXPECT_EQ(parseDecoderMethod("magls"), DecoderMethod::kMagLs);
  EXPECT_EQ(parseDecoderMethod("least_squares"), DecoderMethod::kLeastSquares);
  EXPECT_EQ(parseDecoderMethod("virtual_loudspeakers"), DecoderMethod::kVirtualLoudspeakers);
  for (const auto method : {DecoderMethod::kMagLs, DecoderMethod::kLeastSquares, DecoderMethod::kVirtualLoudspeakers}) {
    EXPECT_EQ(parseDecoderMethod(toString(method)), method);
  }
  expectInputError([] { parseDecoderMethod("allrad"); }, {"allrad", "magls"});
}

TEST(LoudspeakerLayout, NamedLayouts) {
  const auto rings = loudspeakerLayoutByName("paper_rings");
  ASSERT_EQ(rings.size(), 48u);
  int horizontal = 0, up = 0, down = 0;
  for (const auto& d : rings) {
    const double el = std::asin(d.z()) * 180.0 / kPi;
    if (std::abs(el) < 1e-9) ++horizontal;
    if (std::abs(el - 30.0) < 1e-9) ++up;
    if (std::abs(el + 30.0) < 1e-9) ++down;
  }
  EXPECT_EQ(horizontal, 24);
  EXPECT_EQ(up, 12);
  EXPECT_EQ(down, 12);
  EXPECT_EQ(loudspeakerLayoutByName("fibonacci_50").size(), 50u);
  EXPECT_EQ(loudspeakerLayoutByName(kDefaultLoudspeakerLayout).size(), 50u);
  expectInputError([] { loudspeakerLayoutByName("fibonacci_5"); }, {"21"});
  expectInputError([] { loudspeakerLayoutByName("dome"); }, {"dome", "paper_rings"});
}

TEST(LoudspeakerLayout, ParsesDegreeLists) {
  const auto layout = parseLoudspeakerLayout("0,0; 90,0; 180, 0; -90,0; 0,90; 0,-90");
  ASSERT_EQ(layout.size(), 6u);
  EXPECT_NEAR((layout[1] - Eigen::Vector3d(0, 1, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((layout[4] - Eigen::Vector3d(0, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_EQ(parseLoudspeakerLayout(" paper_rings ").size(), 48u);
  expectInputError([] { parseLoudspeakerLayout(""); }, {"empty"});
  expectInputError([] { parseLoudspeakerLayout("0,95"); }, {"elevation"});
  expectInputError([] { parseLoudspeakerLayout("0,0; 0,0"); }, {"0.1 deg"});
  expectInputError([] { parseLoudspeakerLayout("0,0; left"); }, {"left"});
}

const BinauralDecoder& ku100Decoder() {
  static const BinauralDecoder decoder = makeBinauralDecoder(ku100(), 3);
  return decoder;
}

TEST(BinauralDecoderKu100, NinetyDegreesLeftKeepsItdAndIldAsFarAsOrderThreeCan) {
  ASSERT_TRUE(std::filesystem::exists(kuPath()));
  const HrtfSet& set = ku100();
  const std::size_t left = set.nearest(direction(90.0, 0.0));
  ASSERT_GT(set.direction(left).y(), 0.999);
  // Measured errors of the default decoder: ITD -4 us; ILD 0.1, -1.4, 0.4, -2.2, -4.1 dB
  // from 500 Hz to 8 kHz. A real head's side ILD needs more than order 3 from 1 kHz up
  // (the complex fit alone errs by 1.35 dB at 1 kHz), and the diffuse-field covariance
  // constraint, which mixes a little of the near ear into the far one to match the
  // diffuse field's coherence, costs the quiet far ear 3 dB at 8 kHz (docs/binaural_decoders.md).
  expectSameCues(decodeImpulse(ku100Decoder(), set.direction(left)), set.hrir(left), {0.5, 2.0, 1.0, 3.0, 5.0}, 50.0,
                 "KU100 90 deg left");
}

TEST(BinauralDecoderKu100, OrderThreeKeepsTheCuesOnAverage) {
  const DecoderComparison c = compareDecoderToHrtf(ku100Decoder(), ku100(), 100);
  EXPECT_LT(c.ild_error_db_mean, 1.0);  // measured 0.9 dB (200 directions)
  EXPECT_LT(c.itd_error_us, 20.0);      // measured 12 us
  EXPECT_LT(c.diffuse_coherence_error_mean, 0.02);
}

// Prints the table of docs/binaural_decoders.md:
//   test_binaural_decoder --gtest_also_run_disabled_tests --gtest_filter='*DISABLED_PrintComparison*'
TEST(BinauralDecoderKu100, DISABLED_PrintComparisonTable) {
  const HrtfSet& set = ku100();
  std::printf("| decoder | N | ILD 500 | 1k | 2k | 4k | 8k | ILD mean | ITD mean | ITD max | DF level | DF coh. |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const auto print = [&](const std::string& name, int order, const BinauralDecoder& decoder) {
    const DecoderComparison c = compareDecoderToHrtf(decoder, set, 200);
    std::printf("| %s | %d |", name.c_str(), order);
    for (const double e : c.ild_error_db) std::printf(" %.2f |", e);
    std::printf(" **%.2f** | **%.1f** | %.1f | %.2f | %.3f |\n", c.ild_error_db_mean, c.itd_error_us,
                c.itd_error_us_max, c.diffuse_level_error_db_mean, c.diffuse_coherence_error_mean);
  };
  MagLsOptions unconstrained;
  unconstrained.diffuse_field_covariance = false;
  for (int order = 1; order <= 3; ++order) {
    for (const DecoderMethod method :
         {DecoderMethod::kVirtualLoudspeakers, DecoderMethod::kLeastSquares, DecoderMethod::kMagLs}) {
      print(toString(method), order, makeBinauralDecoder(set, order, method));
    }
    print("magls, no covariance constraint", order, makeMagLsDecoder(set, order, unconstrained));
    print("virtual_loudspeakers, paper_rings", order, makeVirtualLoudspeakerDecoder(set, order, paperRingsLayout()));
  }
}
