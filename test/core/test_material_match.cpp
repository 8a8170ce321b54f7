// The library material nearest a fitted absorption (diagnosis/material_match.h), on a
// small library with known curves and on the project's library.
#include <gtest/gtest.h>

#include "room_reverb/diagnosis/material_match.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

AcousticMaterial flat(const std::string& name, double alpha) {
  AcousticMaterial m;
  m.name = name;
  m.absorption.fill(alpha);
  m.scattering.fill(0.1);
  m.source = "test";
  return m;
}

MaterialLibrary threeMaterials() {
  MaterialLibrary library;
  library.add(flat("hard", 0.05));
  library.add(flat("soft", 0.5));
  AcousticMaterial rising = flat("rising", 0.0);
  for (std::size_t b = 0; b < rising.absorption.size(); ++b) rising.absorption[b] = 0.1 * static_cast<double>(b);
  library.add(rising);
  return library;
}

TEST(MaterialMatch, NamesTheMaterialWithTheSmallestWorstBand) {
  OctaveBandValues alpha;
  alpha.fill(0.07);
  const MaterialMatch m = nearestMaterial(alpha, threeMaterials());
  EXPECT_EQ(m.material, "hard");
  EXPECT_NEAR(m.max_difference, 0.02, 1e-12);
  // A curve near "rising" except 0.04 off at 1 kHz (band 4).
  for (std::size_t b = 0; b < alpha.size(); ++b) alpha[b] = 0.1 * static_cast<double>(b) + (b == 4 ? 0.04 : 0.01);
  const MaterialMatch r = nearestMaterial(alpha, threeMaterials());
  EXPECT_EQ(r.material, "rising");
  EXPECT_NEAR(r.max_difference, 0.04, 1e-12);
  EXPECT_DOUBLE_EQ(r.worst_band_hz, 1000.0);
}

TEST(MaterialMatch, IgnoresTheExtrapolatedEndBands) {
  OctaveBandValues alpha;
  alpha.fill(0.5);
  alpha.front() = 0.95;  // 63 Hz
  alpha.back() = 0.0;    // 16 kHz
  const MaterialMatch m = nearestMaterial(alpha, threeMaterials());
  EXPECT_EQ(m.material, "soft");
  EXPECT_DOUBLE_EQ(m.max_difference, 0.0);
}

TEST(MaterialMatch, AFitLikeNothingInTheLibraryIsFarFromEverything) {
  // Hard at low frequencies, very absorbing at 2 kHz only: no material of the three.
  OctaveBandValues alpha;
  alpha.fill(0.05);
  alpha[5] = 0.9;
  // Worst bands: hard 0.85 (2 kHz), rising 0.65 (8 kHz), soft 0.45 (125 Hz, first of
  // the bands where it is 0.45 off).
  const MaterialMatch m = nearestMaterial(alpha, threeMaterials());
  EXPECT_EQ(m.material, "soft");
  EXPECT_NEAR(m.max_difference, 0.45, 1e-12);
  EXPECT_DOUBLE_EQ(m.worst_band_hz, 125.0);
  EXPECT_GT(m.max_difference, kImplausibleAbsorptionDifference);
}

TEST(MaterialMatch, FindsALibraryMaterialFromItsOwnCurve) {
  const MaterialLibrary library = MaterialLibrary::loadDefault();
  const MaterialMatch m = nearestMaterial(library.get("carpet_on_concrete").absorption, library);
  EXPECT_DOUBLE_EQ(m.max_difference, 0.0);
  EXPECT_EQ(library.get(m.material).absorption, library.get("carpet_on_concrete").absorption);
}

TEST(MaterialMatch, AnEmptyLibraryMatchesNothing) {
  OctaveBandValues alpha;
  alpha.fill(0.2);
  const MaterialMatch m = nearestMaterial(alpha, MaterialLibrary());
  EXPECT_TRUE(m.material.empty());
  EXPECT_DOUBLE_EQ(m.max_difference, 0.0);
}

}  // namespace
}  // namespace room_reverb::test
