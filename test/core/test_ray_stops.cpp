// Where the rays aimed past a ceiling's ranged edge stop (vision/ray_stops.h), on clouds of
// known geometry: a 6 m long room seen from its origin, the ceiling 1.2 m above the rig,
// the far wall at x = 5 m.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ray_stops.h"

using namespace room_reverb::core::layout;

namespace {

constexpr double kCeilingZ = 1.2;
constexpr double kWallX = 5.0;

// What a rig at the origin ranges: the ceiling up to `ceiling_to` (x), the far wall at
// kWallX from the floor (-1.4) to the ceiling (only where `wall`), both across y in
// [-2, 2], and a light panel hanging 5 cm below the ceiling between panel_x0 and panel_x1;
// for each ray through a fine grid of directions, the first surface it meets, which gives
// a point where that surface is ranged and none where it is not.
std::vector<WeightedPoint> scan(double ceiling_to, bool wall, double panel_x0 = 0.0, double panel_x1 = 0.0) {
  struct Hit {
    double t = 1e9;
    bool ranged = false;
  };
  std::vector<WeightedPoint> points;
  for (double azimuth = -0.7; azimuth <= 0.7; azimuth += 0.002) {
    for (double elevation = -0.4; elevation <= 0.6; elevation += 0.002) {
      const Eigen::Vector3d d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                              std::sin(elevation));
      Hit first;
      const auto meet = [&](double t, bool ranged, const auto& on) {
        if (t > 0.0 && t < first.t && on(t * d)) first = {t, ranged};
      };
      const auto across = [](const Eigen::Vector3d& p) { return std::abs(p.y()) < 2.0; };
      if (d.z() > 0.0) {
        meet((kCeilingZ - 0.05) / d.z(), true, [&](const Eigen::Vector3d& p) {
          return panel_x1 > panel_x0 && p.x() >= panel_x0 && p.x() <= panel_x1 && across(p);
        });
        const double t = kCeilingZ / d.z();
        meet(t, (t * d).x() <= ceiling_to, [&](const Eigen::Vector3d& p) { return p.x() < kWallX && across(p); });
      }
      meet(kWallX / d.x(), wall, [&](const Eigen::Vector3d& p) { return p.z() >= -1.4 && p.z() <= kCeilingZ && across(p); });
      if (first.ranged) points.push_back({(first.t * d).cast<float>(), 1.0f});
    }
  }
  return points;
}

}  // namespace

TEST(RayStops, AnUnrangedStretchOfCeilingEndsAtTheWallBeyondIt) {
  const RayStops stops(scan(4.1, true));
  const auto wall = wallWhereCeilingRaysStop(stops, 0, false, 4.1, kCeilingZ, {-2.0, 2.0}, 0.2);
  ASSERT_TRUE(wall.has_value());
  EXPECT_NEAR(*wall, kWallX, 0.05);
  // The same on the low side of a mirrored room.
  std::vector<WeightedPoint> mirrored = scan(4.1, true);
  for (WeightedPoint& p : mirrored) p.p.x() = -p.p.x();
  const auto low = wallWhereCeilingRaysStop(RayStops(mirrored), 0, true, 4.1, kCeilingZ, {-2.0, 2.0}, 0.2);
  ASSERT_TRUE(low.has_value());
  EXPECT_NEAR(*low, kWallX, 0.05);
}

TEST(RayStops, ALongUnrangedStretchIsCrossedWindowByWindow) {
  // The ceiling ranged to 2.5 m only (plain plaster under sensor noise): the rays aimed 1-2 m
  // past the edge land on the unranged ceiling and come back with nothing; those aimed
  // further out stop on the wall.
  const RayStops stops(scan(2.5, true));
  const auto wall = wallWhereCeilingRaysStop(stops, 0, false, 2.5, kCeilingZ, {-2.0, 2.0}, 0.2);
  ASSERT_TRUE(wall.has_value());
  EXPECT_NEAR(*wall, kWallX, 0.05);
  // Asked no further than the first window, there is no evidence.
  EXPECT_FALSE(wallWhereCeilingRaysStop(stops, 0, false, 2.5, kCeilingZ, {-2.0, 2.0}, 0.2, 2.0, 2.0));
}

TEST(RayStops, AHangingLightBeforeTheEdgeDoesNotStopTheRaysAimedWellPast) {
  // The panel's shadow ends the ceiling's range at 4.2 m; the panel stops the rays aimed just
  // past it, not those aimed a metre past.
  const RayStops stops(scan(4.2, true, 3.6, 4.2));
  const auto wall = wallWhereCeilingRaysStop(stops, 0, false, 4.2, kCeilingZ, {-2.0, 2.0}, 0.2);
  ASSERT_TRUE(wall.has_value());
  EXPECT_NEAR(*wall, kWallX, 0.05);
}

TEST(RayStops, AWallAtTheEdgeOrNoEvidenceLeavesTheEdge) {
  // The ceiling ranged to the wall: the rays past it stop at the edge.
  EXPECT_FALSE(wallWhereCeilingRaysStop(RayStops(scan(kWallX, true)), 0, false, kWallX, kCeilingZ, {-2.0, 2.0}, 0.2));
  // Nothing ranged past the edge (the wall unranged too): no evidence.
  EXPECT_FALSE(wallWhereCeilingRaysStop(RayStops(scan(4.1, false)), 0, false, 4.1, kCeilingZ, {-2.0, 2.0}, 0.2));
  // An empty lateral extent.
  EXPECT_FALSE(wallWhereCeilingRaysStop(RayStops(scan(4.1, true)), 0, false, 4.1, kCeilingZ, {1.0, 1.0}, 0.2));
}
