// A small, fast version of the BRAS CR2 validation (docs/validation/bras_cr2.md, rerun in
// full by scripts/validate_bras): two of the ten pairs, 10 000 rays. It guards what the
// full run showed within a JND or two: the air-absorption dominated bands and the energy
// ratios. The low bands' known excess (see the document) is held to its measured size so
// that a change that makes it worse fails.
#include <gtest/gtest.h>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/evaluation/parameter_comparison.h"
#include "room_reverb/evaluation/simulated_pairs.h"
#include "test_files.h"

namespace room_reverb::core {
namespace {

const std::string kMeasurements = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/bras_cr2/measured/measurements.yaml";

TEST(BrasValidation, MeasurementsFileHoldsTheTenPairsAndTheTable) {
  const Measurements m = loadMeasurements(kMeasurements);
  ASSERT_EQ(m.pairs.size(), 10u);
  EXPECT_EQ(m.pairs[0].label, "LS01-MP01");
  EXPECT_NEAR(m.pairs[0].source_m.y(), -2.547, 1e-9);  // y-up file turned to z up
  EXPECT_NEAR(m.pairs[9].receiver_m.z(), 1.230, 1e-9);
  EXPECT_EQ(m.mesh_up_axis, UpAxis::kY);
  ASSERT_TRUE(m.air);
  EXPECT_DOUBLE_EQ(m.air->humidity_percent, 41.7);
  EXPECT_EQ(m.parameters.resolution, BandResolution::kThirdOctave);
  ASSERT_EQ(m.parameters.bands_hz.size(), 24u);
  EXPECT_NEAR(m.parameters.d50.back(), 0.8515, 1e-9);  // from percent
}

TEST(BrasValidation, TwoPairsAgreeWithTheMeasuredRoom) {
  const Measurements m = loadMeasurements(kMeasurements);
  const AcousticScene scene(loadMesh(m.mesh_file, m.mesh_up_axis), MaterialLibrary::loadDefault());
  SimulationSettings settings;
  settings.rays.ray_count = 10000;
  settings.ambisonic_order = 0;
  settings.air = *m.air;
  const std::vector<MeasurementPair> pairs = {m.pairs[0], m.pairs[7]};
  std::vector<MetricsReport> reports;
  for (const SimulatedPair& p : simulatePairs(scene, pairs, settings, BandResolution::kThirdOctave)) {
    reports.push_back(p.metrics);
    EXPECT_LT(p.stats.leaked_rays, p.stats.rays / 1000);  // 2 in 100 000 since legs restart on the wall's plane
  }
  const auto octaves = thirdsToOctaves(compareWithMeasured(reports, m.parameters));
  ASSERT_EQ(octaves.size(), 8u);  // 125 Hz .. 16 kHz
  for (const BandComparison& row : octaves) {
    const auto t20 = row.error_jnd[static_cast<std::size_t>(ComparedParameter::kT20)];
    const auto c80 = row.error_jnd[static_cast<std::size_t>(ComparedParameter::kC80)];
    ASSERT_TRUE(t20 && c80) << row.nominal_hz;
    if (row.nominal_hz >= 2000.0) {
      EXPECT_LT(std::abs(*t20), 3.0) << row.nominal_hz;  // 15 %
    } else {
      // The low bands' known excess: +3.6 JND at 125 Hz over all ten pairs, +4.9 JND with
      // these two pairs and 10 000 rays (measured); a JND of margin for platform differences.
      EXPECT_LT(*t20, 6.0) << row.nominal_hz;
      EXPECT_GT(*t20, -1.0) << row.nominal_hz;
    }
    if (row.nominal_hz >= 500.0 && row.nominal_hz <= 4000.0) {
      EXPECT_LT(std::abs(*c80), 2.0) << row.nominal_hz;
    }
  }
}

TEST(BrasValidation, MeasurementFileErrorsNameTheKey) {
  using room_reverb::test::expectInputError;
  expectInputError([] { parseMeasurements("pairs: []\n", "."); }, {"pairs"});
  expectInputError([] { parseMeasurements("pairs:\n  - {source_m: [1, 2], receiver_m: [0, 0, 1]}\n", "."); },
                   {"pairs[0].source_m", "3 numbers"});
  expectInputError([] { parseMeasurements("parameters: {bands_hz: [125, 250], t20_s: [1.0]}\n", "."); },
                   {"parameters.t20_s", "2 numbers"});
  expectInputError([] { parseMeasurements("parameters: {bands_hz: [125], d50_percent: [140]}\n", "."); }, {"D50"});
  expectInputError([] { parseMeasurements("pairs:\n  - {file: a.wav, format: mp3, source_m: [1, 2, 1], receiver_m: [0, 0, 1]}\n", "."); },
                   {"format", "mp3"});
  expectInputError([] { parseMeasurements("just text", "."); }, {"measurements"});
  expectInputError([] { loadMeasurements("/nonexistent/measurements.yaml"); }, {"/nonexistent/measurements.yaml"});
}

}  // namespace
}  // namespace room_reverb::core
