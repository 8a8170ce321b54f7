// Where a horizontal surface ends on one side of the rig (vision/surface_edge.h, a header
// private to the core library), on point distances of known truth.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "surface_edge.h"

using room_reverb::core::layout::surfaceEdge;

namespace {

// A surface seen from 1 m out to `end_m`, its points thinning as the cube of their
// distance cubed beyond 3 m (the ground seen at ever more grazing angles, as spherical stereo
// ranges it), with no step where it ends.
std::vector<double> thinningSurface(double end_m, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> along(1.0, end_m), keep(0.0, 1.0);
  std::vector<double> distances;
  for (int i = 0; i < 20000; ++i) {
    const double d = along(rng);
    if (keep(rng) < std::min(1.0, 27.0 / (d * d * d))) distances.push_back(d);
  }
  return distances;
}

}  // namespace

TEST(SurfaceEdge, AStepIsWhereTheDensityDrops) {
  std::vector<double> distances;
  for (int i = 0; i < 6000; ++i) distances.push_back(0.001 * i);  // 0-6 m, evenly
  const auto edge = surfaceEdge(distances);
  ASSERT_TRUE(edge.has_value());
  EXPECT_TRUE(edge->step);
  EXPECT_NEAR(edge->distance_m, 6.0, 0.05);
}

TEST(SurfaceEdge, ASurfaceThinningOutEndsAtItsFarthestPoint) {
  const std::vector<double> distances = thinningSurface(13.0, 3);
  const auto edge = surfaceEdge(distances);
  ASSERT_TRUE(edge.has_value());
  EXPECT_FALSE(edge->step);
  EXPECT_NEAR(edge->distance_m, 13.0, 0.1);
}

// Strays ranged twice as far (mismatches at a far wall's rim) lie beyond an empty stretch
// of a tenth of the surface's distance: the surface ends where it does, not where they do.
TEST(SurfaceEdge, StraysBeyondAGapAreNoPartOfTheSurface) {
  std::vector<double> distances = thinningSurface(13.0, 4);
  for (double stray : {26.0, 26.2, 26.4, 26.5, 26.9, 27.4}) distances.push_back(stray);
  const auto edge = surfaceEdge(distances);
  ASSERT_TRUE(edge.has_value());
  EXPECT_FALSE(edge->step);
  EXPECT_NEAR(edge->distance_m, 13.0, 0.1);
  EXPECT_FALSE(surfaceEdge({1.0, 2.0, 3.0}).has_value());  // fewer points than min_points
}
