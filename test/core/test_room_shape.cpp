// Scenes built from a room model decide inside and outside from the model's solids: exact
// where objects touch the walls, the floor and each other, or overlap, and the object a
// position falls in is named. Scenes from a mesh keep crossing parity.
#include <gtest/gtest.h>

#include <cmath>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/common/convex_polygons.h"
#include "room_reverb/common/error.h"
#include "test_files.h"
#include "test_rooms.h"

using namespace room_reverb::core;

namespace {

using room_reverb::test::expectInputError;

CuboidObject box(const std::string& label, const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw = 0.0) {
  return room_reverb::test::woodCuboid(label, center, size, yaw);
}

RoomModel emptyRoom(const Eigen::Vector3d& size) { return room_reverb::test::plasterRoom(size); }

AcousticScene sceneOf(const RoomModel& model) { return roomModelToScene(model, MaterialLibrary::loadDefault()); }

const Eigen::Vector3d kUnitCube(1.0, 1.0, 1.0);

}  // namespace

TEST(RoomShape, ObjectsFlushWithWallsFloorCeilingAndEachOtherLeaveTheAirBetweenThemInside) {
  RoomModel model = emptyRoom({4.0, 3.0, 2.5});
  model.objects = {box("left", {1.5, 1.5, 0.5}, kUnitCube),                 // on the floor
                   box("right", {2.5, 1.5, 0.5}, kUnitCube),                // against "left" at x = 2
                   box("on_top", {2.0, 1.5, 1.25}, {1.0, 1.0, 0.5}),          // on both, x 1.5..2.5
                   box("tall", {0.25, 1.5, 1.25}, {0.5, 1.0, 2.5}),           // wall_x_min, floor, ceiling
                   box("corner", {3.75, 2.75, 1.25}, {0.5, 0.5, 2.5})};       // two walls, floor, ceiling
  const AcousticScene scene = sceneOf(model);
  ASSERT_NE(scene.roomShape(), nullptr);
  EXPECT_TRUE(scene.isInside({3.0, 0.5, 1.2}));    // free air
  EXPECT_TRUE(scene.isInside({2.0, 1.5, 2.0}));    // above the stack
  EXPECT_TRUE(scene.isInside({1.2, 1.5, 1.25}));   // in the gap between "tall" and "on_top"
  EXPECT_TRUE(scene.isInside({3.75, 2.0, 1.25}));  // in front of "corner"
  EXPECT_FALSE(scene.isInside({1.5, 1.5, 0.5}));
  EXPECT_FALSE(scene.isInside({2.5, 1.5, 0.5}));
  EXPECT_FALSE(scene.isInside({2.0, 1.5, 1.25}));
  EXPECT_FALSE(scene.isInside({0.25, 1.5, 2.4}));
  EXPECT_FALSE(scene.isInside({3.9, 2.9, 0.1}));
  EXPECT_FALSE(scene.isInside({4.1, 1.5, 1.0}));   // beyond a wall
  EXPECT_FALSE(scene.isInside({2.0, 1.5, 2.6}));   // above the ceiling
  scene.requireInside({3.0, 0.5, 1.2}, "source");
  scene.requireInside({2.0, 1.5, 2.0}, "listener");
}

TEST(RoomShape, OverlappingAndTurnedObjectsAreSolidThroughout) {
  RoomModel model = emptyRoom({5.0, 4.0, 3.0});
  model.objects = {box("a", {1.5, 1.5, 0.5}, kUnitCube), box("b", {1.8, 1.5, 0.5}, kUnitCube),
                   box("beam", {3.5, 2.5, 1.0}, {2.0, 0.2, 1.0}, M_PI / 4.0)};
  const AcousticScene scene = sceneOf(model);
  EXPECT_FALSE(scene.isInside({1.65, 1.5, 0.5}));  // in both
  EXPECT_FALSE(scene.isInside({2.2, 1.5, 0.5}));   // in "b" only
  EXPECT_TRUE(scene.isInside({1.65, 1.5, 1.2}));
  // 0.7 m along the beam's own x axis from its centre, and 0.7 m across it.
  const Eigen::Vector3d along(std::cos(M_PI / 4.0), std::sin(M_PI / 4.0), 0.0);
  const Eigen::Vector3d across(-along.y(), along.x(), 0.0);
  EXPECT_FALSE(scene.isInside(Eigen::Vector3d(3.5, 2.5, 1.0) + 0.7 * along));
  EXPECT_TRUE(scene.isInside(Eigen::Vector3d(3.5, 2.5, 1.0) + 0.7 * across));
  EXPECT_TRUE(scene.isInside(Eigen::Vector3d(3.5, 2.5, 1.0) + 0.11 * across));
  EXPECT_FALSE(scene.isInside(Eigen::Vector3d(3.5, 2.5, 1.0) + 0.09 * across));
}

TEST(RoomShape, APositionInAnObjectIsRefusedNamingIt) {
  RoomModel model = emptyRoom({5.0, 4.0, 3.0});
  model.objects = {box("table", {3.0, 3.0, 0.4}, {1.0, 1.0, 0.8}), box("chair", {0.5, 0.5, 0.5}, kUnitCube),
                   box("sofa", {4.0, 1.0, 0.4}, {1.0, 1.0, 0.8}), box("cabinet", {2.0, 1.0, 1.0}, {1.0, 1.0, 2.0}),
                   box("drawer", {2.0, 1.0, 1.0}, {0.6, 0.6, 0.6})};
  const AcousticScene scene = sceneOf(model);
  try {
    scene.requireInside({2.0, 1.0, 1.0}, "listener");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "listener (2, 1, 1) m is inside object 3 (cabinet)");
  }
  expectInputError([&] { scene.requireInside({6.0, 1.0, 1.0}, "source"); },
                   {"source (6, 1, 1) m is outside the room", "[0, 5] x [0, 4] x [0, 3] m"});
  expectInputError([&] { scene.requireInside({3.0, 3.0, 0.805}, "source"); }, {"closer than 0.01"});  // above the table
  // The simulation refuses it the same way rather than rendering silence.
  SimulationSettings settings;
  expectInputError([&] { simulateRoom(scene, {4.0, 3.0, 1.5}, {0.5, 0.5, 0.2}, settings); },
                   {"listener (0.5, 0.5, 0.2) m is inside object 1 (chair)"});
}

TEST(RoomShape, WithoutACeilingInsideMeansWithinTheWalls) {
  RoomModel model = emptyRoom({6.0, 5.0, 3.0});
  model.has_ceiling = false;
  model.surfaces.erase("ceiling");
  model.objects = {box("planter", {1.0, 1.0, 0.5}, kUnitCube)};
  const AcousticScene scene = sceneOf(model);
  EXPECT_FALSE(scene.closed());
  EXPECT_TRUE(scene.isInside({3.0, 2.5, 2.9}));
  EXPECT_FALSE(scene.isInside({3.0, 2.5, 3.1}));
  EXPECT_FALSE(scene.isInside({1.0, 1.0, 0.5}));
}

TEST(RoomShape, VolumeIsTheBoxLessTheUnionOfTheObjectsInsideIt) {
  RoomModel model = emptyRoom({5.0, 4.0, 3.0});
  model.objects = {box("a", {1.5, 1.5, 0.5}, kUnitCube),
                   box("b", {2.0, 1.5, 0.5}, kUnitCube),      // half inside "a": together 1.5 m^3
                   box("c", {3.0, 1.5, 0.5}, kUnitCube),      // flush with "b": 1 m^3
                   box("out", {0.0, 3.0, 0.5}, kUnitCube),    // half through wall_x_min: 0.5 m^3
                   box("up", {4.0, 3.0, 2.75}, kUnitCube)};   // a quarter through the ceiling: 0.75 m^3
  const AcousticScene scene = sceneOf(model);
  EXPECT_NEAR(scene.volumeM3(), 60.0 - 1.5 - 1.0 - 0.5 - 0.75, 1e-9);

  // Two unit cubes on one centre, one turned 45 degrees: they share a regular octagon of
  // inradius 0.5, area 2 (sqrt(2) - 1); their union is 2 - that.
  RoomModel star = emptyRoom({5.0, 4.0, 3.0});
  star.objects = {box("a", {2.0, 2.0, 0.5}, kUnitCube), box("b", {2.0, 2.0, 0.5}, kUnitCube, M_PI / 4.0)};
  const AcousticScene star_scene = sceneOf(star);
  EXPECT_NEAR(star_scene.volumeM3(), 60.0 - (2.0 - 2.0 * (std::sqrt(2.0) - 1.0)), 1e-9);
  const RoomShape& shape = *star_scene.roomShape();
  EXPECT_NEAR(cuboidOverlapM3(shape.objects[0], shape.objects[1]), 2.0 * (std::sqrt(2.0) - 1.0), 1e-9);

  // Apart, inside and not overlapping, the solids' volume is the mesh's.
  RoomModel apart = emptyRoom({5.0, 4.0, 3.0});
  apart.objects = {box("a", {1.0, 1.0, 0.5}, kUnitCube), box("t", {3.0, 2.0, 1.0}, {1.0, 0.5, 0.4}, 0.3)};
  const AcousticScene from_mesh(roomModelToMesh(apart), MaterialLibrary::loadDefault());
  EXPECT_NEAR(sceneOf(apart).volumeM3(), from_mesh.volumeM3(), 1e-9);
  EXPECT_NEAR(sceneOf(apart).volumeM3(), 60.0 - 1.0 - 0.2, 1e-9);
}

TEST(RoomShape, UnionAreaOfPolygonsThatTouchShareOrNest) {
  const Polygon2d unit = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const Polygon2d right = {{1, 0}, {2, 0}, {2, 1}, {1, 1}};      // shares an edge, run the other way
  const Polygon2d half = {{0.5, 0}, {1.5, 0}, {1.5, 1}, {0.5, 1}};  // shares parts of two edges
  const Polygon2d inner = {{0.2, 0.2}, {0.4, 0.2}, {0.4, 0.4}, {0.2, 0.4}};
  EXPECT_NEAR(unionArea({unit}), 1.0, 1e-12);
  EXPECT_NEAR(unionArea({unit, right}), 2.0, 1e-12);
  EXPECT_NEAR(unionArea({unit, half}), 1.5, 1e-12);
  EXPECT_NEAR(unionArea({unit, unit}), 1.0, 1e-12);
  EXPECT_NEAR(unionArea({unit, inner}), 1.0, 1e-12);
  EXPECT_NEAR(unionArea({unit, right, half, inner}), 2.0, 1e-12);
}

TEST(RoomShape, AMeshSceneKeepsCrossingParity) {
  RoomModel model = emptyRoom({5.0, 4.0, 3.0});
  model.objects = {box("table", {2.0, 2.0, 0.4}, {1.0, 1.0, 0.8})};
  const AcousticScene scene(roomModelToMesh(model), MaterialLibrary::loadDefault());
  EXPECT_EQ(scene.roomShape(), nullptr);
  EXPECT_TRUE(scene.isInside({4.0, 3.0, 1.5}));
  EXPECT_FALSE(scene.isInside({2.0, 2.0, 0.4}));
  EXPECT_FALSE(scene.isInside({6.0, 2.0, 1.0}));
  // A mesh has no object names: the message is the general one.
  expectInputError([&] { scene.requireInside({2.0, 2.0, 0.4}, "source"); },
                   {"source (2, 2, 0.4) m is outside the room or inside an object or wall"});
  // Its volume is the divergence sum over the triangles.
  EXPECT_NEAR(scene.volumeM3(), 60.0 - 0.8, 1e-9);
}
