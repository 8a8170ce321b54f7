// The ray caster of room models (vision/room_raycast.h): the cull of objects for a bundle
// of rays at a patch (objectsInReach) must keep every object such a ray meets, since the
// surface patches' visibility test casts against that list alone and must find what a
// cast against every object finds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "room_reverb/vision/room_raycast.h"

using namespace room_reverb::core;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A room so large that a ray meets every object it crosses before it leaves the box.
CaptureGeometry scatteredObjects(std::mt19937& random, int count) {
  std::uniform_real_distribution<double> place(-6.0, 6.0), side(0.05, 2.5), yaw(-kPi, kPi);
  CaptureGeometry geometry;
  geometry.size_m = Eigen::Vector3d(1000.0, 1000.0, 1000.0);
  for (int k = 0; k < count; ++k) {
    CaptureCuboid cuboid;
    const Eigen::Vector3d offset(place(random), place(random), place(random));
    cuboid.center_m = Eigen::Vector3d(500.0, 500.0, 500.0) + offset;
    cuboid.half_size_m = Eigen::Vector3d(side(random), side(random), side(random));
    cuboid.local_to_room = Eigen::AngleAxisd(yaw(random), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    geometry.objects.push_back(cuboid);
  }
  return geometry;
}

}  // namespace

TEST(RoomRaycast, CandidateCastMatchesTheFullCast) {
  std::mt19937 random(5);
  const CaptureGeometry geometry = scatteredObjects(random, 12);
  std::vector<std::size_t> all(geometry.objects.size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = k;
  std::normal_distribution<double> gauss;
  const Eigen::Vector3d origin(500.0, 500.0, 500.0);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
    const SurfaceHit a = castRay(geometry, origin, d), b = castRay(geometry, origin, d, all);
    ASSERT_EQ(a.sky, b.sky);
    ASSERT_EQ(a.object_id, b.object_id);
    ASSERT_EQ(a.distance_m, b.distance_m);
  }
}

TEST(RoomRaycast, ObjectsInReachKeepsEveryObjectARayMeets) {
  std::mt19937 random(6);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t listed = 0, offered = 0, met = 0;
  for (int scene = 0; scene < 40; ++scene) {
    const CaptureGeometry geometry = scatteredObjects(random, 10);
    const Eigen::Vector3d origin =
        Eigen::Vector3d(500.0, 500.0, 500.0) + 3.0 * Eigen::Vector3d(gauss(random), gauss(random), gauss(random));
    for (int bundle = 0; bundle < 30; ++bundle) {
      // A patch 1-12 m away, 0.1-0.6 m across, seen beyond_m past its points.
      const Eigen::Vector3d toward = Eigen::Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
      const Eigen::Vector3d centre = origin + (1.0 + 11.0 * unit(random)) * toward;
      const double radius = 0.1 + 0.5 * unit(random), beyond = 0.01 + 0.1 * unit(random);
      const std::vector<std::size_t> reach = objectsInReach(geometry, origin, centre, radius, beyond);
      listed += reach.size();
      offered += geometry.objects.size();
      for (std::size_t j = 1; j < reach.size(); ++j) ASSERT_LT(reach[j - 1], reach[j]);
      for (int ray = 0; ray < 40; ++ray) {
        Eigen::Vector3d offset;
        do offset = Eigen::Vector3d(2.0 * unit(random) - 1.0, 2.0 * unit(random) - 1.0, 2.0 * unit(random) - 1.0);
        while (offset.norm() > 1.0);
        const Eigen::Vector3d point = centre + radius * offset;
        const double range = (point - origin).norm();
        const Eigen::Vector3d d = (point - origin) / range;
        for (std::size_t k = 0; k < geometry.objects.size(); ++k) {
          const SurfaceHit hit = castRay(geometry, origin, d, {k});
          if (hit.sky || hit.object_id != 6 + k || hit.distance_m > range + beyond) continue;
          ++met;
          EXPECT_NE(std::find(reach.begin(), reach.end(), k), reach.end())
              << "object " << k << " met at " << hit.distance_m << " m on a ray to a point " << range << " m away";
        }
      }
    }
  }
  std::printf("[ measured ] objects in reach: %.1f %% of those offered; %zu meetings checked\n",
              100.0 * static_cast<double>(listed) / static_cast<double>(offered), met);
  EXPECT_GT(met, 1000u);
  EXPECT_LT(listed, offered);  // the cull leaves objects out
}
