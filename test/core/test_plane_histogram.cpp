// Planes as peaks of a histogram (src/core/vision/plane_histogram.h), on coordinates drawn
// with known layers: a wall behind units found as an outer layer, with the dip before the
// units' fronts; a single noisy layer gives one peak.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "plane_histogram.h"

namespace {

using namespace room_reverb::core::layout;

void addLayer(std::vector<double>& values, std::mt19937& rng, double at, double sigma, int count) {
  std::normal_distribution<double> noise(at, sigma);
  for (int i = 0; i < count; ++i) values.push_back(noise(rng));
}

const PlanePeak* peakNear(const std::vector<PlanePeak>& peaks, double at, double within) {
  for (const PlanePeak& p : peaks) {
    if (std::abs(p.position_m - at) <= within) return &p;
  }
  return nullptr;
}

// Shelving's fronts 5.45 m from the rig, densest; the wall 5.68 m out, seen between and
// above the shelves; points smeared between the two (the stereo's windows straddle the
// step). At 1 % range noise a plane's window there is +-17 cm: the wall's reaches into
// the fronts.
std::vector<double> wallBehindUnits(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<double> values;
  addLayer(values, rng, 5.45, 0.05, 4000);
  addLayer(values, rng, 5.68, 0.05, 2200);
  std::uniform_real_distribution<double> between(5.45, 5.68);
  for (int i = 0; i < 1500; ++i) values.push_back(between(rng));
  addLayer(values, rng, 1.2, 0.02, 3000);  // the wall behind the rig
  return values;
}

TEST(PlaneHistogram, AWallBehindUnitsIsAnOuterLayerWithTheDipBeforeTheUnits) {
  const PlaneSpread spread;  // 1 %, 3 sigma
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const PlaneHistogram histogram(wallBehindUnits(seed), 0.01);
    // Over the full window the fronts suppress it: they are the last layer.
    const auto plain = histogram.peaks(spread, 200.0, 1.4);
    EXPECT_EQ(peakNear(plain, 5.68, 0.08), nullptr) << "seed " << seed;
    ASSERT_NE(peakNear(plain, 5.45, 0.05), nullptr) << "seed " << seed;
    // Against the outer flank the wall stands out.
    const auto peaks = histogram.peaks(spread, 200.0, 1.4, 3.0);
    const PlanePeak* wall = peakNear(peaks, 5.68, 0.05);
    ASSERT_NE(wall, nullptr) << "seed " << seed;
    EXPECT_GE(wall->outer_contrast, 3.0);
    // Its refinement stops at the dip before the fronts.
    ASSERT_FALSE(std::isnan(wall->inner_valley_m)) << "seed " << seed;
    EXPECT_GT(wall->inner_valley_m, 5.45) << "seed " << seed;
    EXPECT_LT(wall->inner_valley_m, wall->position_m) << "seed " << seed;
    // The fronts and the wall behind the rig keep their peaks, with no dip of their own.
    const PlanePeak* fronts = peakNear(peaks, 5.45, 0.05);
    ASSERT_NE(fronts, nullptr);
    EXPECT_TRUE(std::isnan(fronts->inner_valley_m));
    ASSERT_NE(peakNear(peaks, 1.2, 0.03), nullptr);
  }
}

TEST(PlaneHistogram, OneNoisyLayerIsOnePeak) {
  const PlaneSpread spread;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    std::mt19937 rng(seed);
    std::vector<double> values;
    addLayer(values, rng, 5.0, 0.05, 5000);
    addLayer(values, rng, -3.0, 0.03, 5000);
    const PlaneHistogram histogram(values, 0.01);
    const auto peaks = histogram.peaks(spread, 200.0, 1.4, 3.0);
    ASSERT_EQ(peaks.size(), 2u) << "seed " << seed;
    EXPECT_NEAR(peaks[0].position_m, -3.0, 0.03);
    EXPECT_NEAR(peaks[1].position_m, 5.0, 0.03);
    for (const PlanePeak& p : peaks) EXPECT_TRUE(std::isnan(p.inner_valley_m)) << "seed " << seed;
  }
}

}  // namespace
