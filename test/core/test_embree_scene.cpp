// The Embree wrapper's two BVHs (embree_scene.h): the watertight one behind intersect()
// and occluded(), and the fast one behind intersectFast(), which asks the watertight one
// again when it finds nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/embree_scene.h"
#include "room_reverb/acoustics/triangle_mesh.h"
#include "room_reverb/acoustics/room_model.h"
#include "shoebox.h"
#include "test_rooms.h"

using namespace room_reverb::core;

namespace {

Eigen::Vector3d uniformDirection(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double z = 2.0 * unit(rng) - 1.0, phi = 2.0 * 3.14159265358979323846 * unit(rng);
  const double r = std::sqrt(1.0 - z * z);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

TEST(EmbreeScene, TheFastBvhFindsTheWatertightHits) {
  // A room with objects: from random points in free air, both find the same triangle at
  // the same distance, up to the float rounding of two intersection tests.
  RoomModel model = room_reverb::test::plasterRoom({6.0, 5.0, 3.0});
  model.objects.push_back(room_reverb::test::woodCuboid("table", {2.0, 3.8, 0.4}, {1.2, 0.8, 0.8}));
  model.objects.push_back(room_reverb::test::woodCuboid("cabinet", {4.8, 1.0, 1.0}, {0.5, 0.6, 2.0}, 0.4));
  const AcousticScene scene = roomModelToScene(model, MaterialLibrary::loadDefault(), {});
  const EmbreeScene& geometry = scene.geometry();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int rays = 0, same = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d origin(0.2 + 5.6 * unit(rng), 0.2 + 4.6 * unit(rng), 1.0 + 1.8 * unit(rng));  // above the table
    const Eigen::Vector3d direction = uniformDirection(rng);
    const RayHit watertight = geometry.intersect(origin, direction);
    const RayHit fast = geometry.intersectFast(origin, direction);
    ASSERT_TRUE(watertight.hit);
    ASSERT_TRUE(fast.hit) << "a ray from inside a closed room found nothing";
    ++rays;
    EXPECT_NEAR(fast.distance_m, watertight.distance_m, 1e-4);
    // At a shared edge the two may name either of its triangles.
    if (fast.triangle == watertight.triangle) ++same;
  }
  EXPECT_GT(same, rays - rays / 1000);
}

TEST(EmbreeScene, ARayThroughASharedEdgeFindsAWall) {
  // Each wall of a shoebox is two triangles meeting along its diagonal. Rays aimed at
  // points of those diagonals, where a test that is not watertight may slip between the
  // two, must hit the wall at the point aimed at (the legs CR2's run does let through the
  // fast BVH are in LegsThatSlipThroughTheFastBvhAreCaught).
  const Eigen::Vector3d size(5.0, 4.0, 3.0);
  const TriangleMesh mesh = room_reverb::test::shoeboxMesh(size);
  const EmbreeScene geometry(mesh);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t t = 0; t < mesh.triangleCount(); t += 2) {
    // Triangles (q0, q1, q2) and (q0, q2, q3) share the edge q0-q2.
    const Eigen::Vector3d a = mesh.vertices[mesh.triangles[t][0]], b = mesh.vertices[mesh.triangles[t][2]];
    for (int i = 0; i < 500; ++i) {
      const Eigen::Vector3d target = a + (0.02 + 0.96 * unit(rng)) * (b - a);
      const Eigen::Vector3d origin(0.5 + 4.0 * unit(rng), 0.5 + 3.0 * unit(rng), 0.5 + 2.0 * unit(rng));
      const Eigen::Vector3d direction = (target - origin).normalized();
      const RayHit hit = geometry.intersectFast(origin, direction);
      ASSERT_TRUE(hit.hit) << "slipped through the edge at " << target.transpose();
      EXPECT_NEAR(hit.distance_m, (target - origin).norm(), 1e-4);
    }
  }
  // Straight down onto the floor's diagonal from (0, 0) to (5, 4), and along the walls'
  // planes' normals onto theirs: rays that meet the edge itself.
  for (int i = 1; i < 2000; ++i) {
    const double s = static_cast<double>(i) / 2000.0;
    const RayHit down = geometry.intersectFast({5.0 * s, 4.0 * s, 1.5}, {0.0, 0.0, -1.0});
    ASSERT_TRUE(down.hit) << "slipped through the floor at s = " << s;
    EXPECT_NEAR(down.distance_m, 1.5, 1e-5);
  }
}

TEST(EmbreeScene, ARealHoleIsNotClosedByTheSecondQuery) {
  // Without one of the floor's two triangles, a ray straight down through the missing half
  // finds nothing in either BVH: the tracer counts it as a leak.
  TriangleMesh mesh = room_reverb::test::shoeboxMesh({5.0, 4.0, 3.0});
  mesh.triangles.erase(mesh.triangles.begin());
  mesh.triangle_material.erase(mesh.triangle_material.begin());
  const EmbreeScene geometry(mesh);
  // The removed triangle is (0,0,0) (5,0,0) (5,4,0): below (4, 1) lies the missing half.
  EXPECT_FALSE(geometry.intersectFast({4.0, 1.0, 1.5}, {0.0, 0.0, -1.0}).hit);
  EXPECT_FALSE(geometry.intersect({4.0, 1.0, 1.5}, {0.0, 0.0, -1.0}).hit);
  // The other half is still there.
  const RayHit kept = geometry.intersectFast({1.0, 3.0, 1.5}, {0.0, 0.0, -1.0});
  ASSERT_TRUE(kept.hit);
  EXPECT_NEAR(kept.distance_m, 1.5, 1e-6);
}

TEST(EmbreeScene, LegsThatSlipThroughTheFastBvhAreCaught) {
  // Four legs of the accurate BRAS CR2 run (100 000 rays, seed 1, 43 million legs) that the
  // fast BVH's Möller-Trumbore test lets through between two triangles: the second query
  // gives each the wall the watertight test finds.
  const TriangleMesh mesh = loadMesh(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/bras_cr2/geometry/cr2_scene9.ac", UpAxis::kY);
  const EmbreeScene geometry(mesh);
  struct Leg {
    Eigen::Vector3d origin, direction;
  };
  const Leg legs[] = {
      {{3.1441579171556167, 1.4716553647705062, 0.86991770660746726}, {-0.83204572597338655, -0.33730749490465833, -0.44036753260267303}},
      {{1.1809906340087599, 3.4271208402291151, 2.9879989999999998}, {-0.45552421932206272, 0.29171003770009019, -0.84107249361516823}},
      {{2.4949929006294647, -3.2622027399294455, 2.5159794032682776}, {-0.89432811538789025, 0.15988591602531588, -0.41786806037730451}},
      {{0.4709578445759206, -0.84678542385747857, 1.0000000003241976e-06}, {0.23934759874708747, 0.62040532760839573, 0.74686675950206982}},
  };
  for (const Leg& leg : legs) {
    const RayHit watertight = geometry.intersect(leg.origin, leg.direction, 1e-7);
    const RayHit fast = geometry.intersectFast(leg.origin, leg.direction, 1e-7);
    ASSERT_TRUE(watertight.hit);
    ASSERT_TRUE(fast.hit) << "from " << leg.origin.transpose();
    EXPECT_EQ(fast.triangle, watertight.triangle);
    EXPECT_NEAR(fast.distance_m, watertight.distance_m, 1e-6);
  }
}
