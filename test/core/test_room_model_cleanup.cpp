// A fitted room model made simulable: objects cut back to the room box (exactly where they
// are square to it, conservatively where turned), slivers and hidden objects dropped, free
// air cleared around the rig by the least volume; and a kitchen whose fit put the rig
// inside a cabinet simulates afterwards, from the rig.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/metrics/impulse_response_metrics.h"
#include "room_reverb/synthetic_capture/cluttered_rooms.h"
#include "room_reverb/common/error.h"
#include "room_reverb/vision/room_model_cleanup.h"
#include "test_files.h"
#include "test_rooms.h"

using namespace room_reverb::core;

namespace {

using room_reverb::test::expectInputError;

CuboidObject box(const std::string& label, const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw = 0.0) {
  return room_reverb::test::woodCuboid(label, center, size, yaw);
}

RoomModel room(const Eigen::Vector3d& size, const Eigen::Vector3d& rig) { return room_reverb::test::plasterRoom(size, rig); }

// The eight corners of an object, in the room frame.
std::vector<Eigen::Vector3d> corners(const CuboidObject& object) {
  std::vector<Eigen::Vector3d> out;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d sign(c & 1 ? 0.5 : -0.5, c & 2 ? 0.5 : -0.5, c & 4 ? 0.5 : -0.5);
    out.push_back(fromCuboidFrame(object, sign.cwiseProduct(object.size_m)));
  }
  return out;
}

bool mentions(const std::vector<std::string>& notes, const std::vector<std::string>& fragments) {
  return std::any_of(notes.begin(), notes.end(), [&](const std::string& note) {
    return std::all_of(fragments.begin(), fragments.end(),
                       [&](const std::string& f) { return note.find(f) != std::string::npos; });
  });
}

std::string joined(const std::vector<std::string>& notes) {
  std::string out;
  for (const auto& n : notes) out += n + "\n";
  return out;
}

const Eigen::Vector3d kFarRig(0.2, 3.8, 2.8);  // a corner no test object comes near

}  // namespace

TEST(RoomModelCleanup, ObjectsSquareToTheBoxAreCutBackExactly) {
  RoomModel model = room({5.0, 4.0, 3.0}, kFarRig);
  model.objects = {box("cabinet", {4.8, 2.0, 1.5}, {1.0, 1.0, 1.0}),           // x 4.3..5.3
                   box("column", {1.0, 1.0, 1.5}, {0.5, 0.5, 4.0}),            // z -0.5..3.5
                   box("turned", {2.5, 3.9, 0.5}, {0.6, 1.0, 1.0}, M_PI / 2),  // its own x: y 3.6..4.2
                   box("inside", {2.5, 2.0, 0.5}, {1.0, 1.0, 1.0})};
  const auto notes = cleanUpRoomModel(model);
  ASSERT_EQ(model.objects.size(), 4u);
  EXPECT_NEAR(model.objects[0].center_m.x(), 4.65, 1e-12);
  EXPECT_NEAR(model.objects[0].size_m.x(), 0.7, 1e-12);
  EXPECT_EQ(model.objects[0].size_m.tail<2>(), Eigen::Vector2d(1.0, 1.0));
  EXPECT_NEAR(model.objects[1].center_m.z(), 1.5, 1e-12);
  EXPECT_NEAR(model.objects[1].size_m.z(), 3.0, 1e-12);
  // Turned a quarter, its own x runs along the room's y: the cut shortens its own x.
  EXPECT_NEAR(model.objects[2].size_m.x(), 0.4, 1e-12);
  EXPECT_EQ(model.objects[2].size_m.y(), 1.0);
  EXPECT_NEAR(model.objects[2].center_m.y(), 3.8, 1e-12);
  EXPECT_EQ(model.objects[2].yaw_rad, M_PI / 2);
  EXPECT_EQ(model.objects[3].center_m, Eigen::Vector3d(2.5, 2.0, 0.5));
  ASSERT_EQ(notes.size(), 3u) << joined(notes);
  EXPECT_EQ(notes[0], "object 0 (cabinet) cut back to the room box: it reached 0.30 m through wall_x_max");
  EXPECT_EQ(notes[1], "object 1 (column) cut back to the room box: it reached 0.50 m through floor, 0.50 m through ceiling");
  EXPECT_TRUE(mentions(notes, {"object 2 (turned)", "0.20 m through wall_y_max"})) << joined(notes);
}

TEST(RoomModelCleanup, ATurnedObjectIsCutAlongItsAxisUntilItsDeepestCornerTouchesTheWall) {
  RoomModel model = room({5.0, 4.0, 3.0}, kFarRig);
  const double yaw = 0.1;
  model.objects = {box("sideboard", {4.8, 2.0, 0.5}, {1.0, 0.4, 1.0}, yaw)};
  cleanUpRoomModel(model);
  ASSERT_EQ(model.objects.size(), 1u);
  const CuboidObject& cut = model.objects[0];
  // Its +x end moves in until the corner (u, -0.2) reaches x = 5:
  // 4.8 + u cos(yaw) + 0.2 sin(yaw) = 5.
  const double u = (0.2 - 0.2 * std::sin(yaw)) / std::cos(yaw);
  EXPECT_NEAR(cut.size_m.x(), 0.5 + u, 1e-12);
  EXPECT_EQ(cut.size_m.y(), 0.4);
  EXPECT_EQ(cut.yaw_rad, yaw);
  double max_x = -1.0;
  for (const auto& corner : corners(cut)) max_x = std::max(max_x, corner.x());
  EXPECT_NEAR(max_x, 5.0, 1e-12);
  // Its -x end did not move.
  const CuboidObject original = box("sideboard", {4.8, 2.0, 0.5}, {1.0, 0.4, 1.0}, yaw);
  EXPECT_NEAR((fromCuboidFrame(cut, {-0.5 * cut.size_m.x(), 0.0, 0.0}) - fromCuboidFrame(original, {-0.5, 0.0, 0.0})).norm(), 0.0, 1e-12);
}

TEST(RoomModelCleanup, SliversAndObjectsOutsideAreDroppedThinFitsAreKept) {
  RoomModel model = room({5.0, 4.0, 3.0}, kFarRig);
  model.objects = {box("stray", {5.02, 2.0, 1.0}, {0.1, 1.0, 1.0}),        // 0.03 m inside
                   box("facade", {6.0, 2.0, 1.0}, {0.5, 1.0, 1.0}),        // all outside
                   box("worktop", {2.5, 0.3, 0.92}, {2.0, 0.6, 0.04}),     // thin as fitted
                   box("shelf", {0.1, 2.0, 1.5}, {0.6, 1.0, 0.03})};       // thin, cut in x to 0.4
  const auto notes = cleanUpRoomModel(model);
  ASSERT_EQ(model.objects.size(), 2u) << joined(notes);
  EXPECT_EQ(model.objects[0].label, "worktop");
  EXPECT_EQ(model.objects[1].label, "shelf");
  EXPECT_NEAR(model.objects[1].size_m.x(), 0.4, 1e-12);
  EXPECT_EQ(model.objects[1].size_m.z(), 0.03);
  EXPECT_TRUE(mentions(notes, {"object 0 (stray) dropped: 0.03 m thin once cut back", "0.07 m through wall_x_max"}))
      << joined(notes);
  EXPECT_TRUE(mentions(notes, {"object 1 (facade) dropped: it lies wholly outside the room box"})) << joined(notes);
}

TEST(RoomModelCleanup, ObjectsHiddenInsideOthersAreDroppedPartialOverlapsStay) {
  RoomModel model = room({5.0, 4.0, 3.0}, kFarRig);
  model.objects = {box("oven", {1.0, 0.3, 0.45}, {0.6, 0.6, 0.9}),          // inside the counter
                   box("counter", {2.0, 0.3, 0.45}, {3.0, 0.6, 0.9}),
                   box("counter", {2.0, 0.3, 0.45}, {3.0, 0.6, 0.9}),        // the same, twice
                   box("stool", {3.5, 0.7, 0.3}, {0.6, 0.6, 0.6}),           // a sixth in the counter
                   box("drawer", {3.55, 0.3, 0.45}, {0.3, 0.6, 0.9})};       // x 3.4..3.7: a third in
  const auto notes = cleanUpRoomModel(model);
  ASSERT_EQ(model.objects.size(), 3u) << joined(notes);
  EXPECT_EQ(model.objects[0].label, "counter");
  EXPECT_EQ(model.objects[1].label, "stool");
  EXPECT_EQ(model.objects[2].label, "drawer");
  EXPECT_TRUE(mentions(notes, {"object 0 (oven) dropped: 100 % of it lies inside object 1 (counter)"})) << joined(notes);
  EXPECT_TRUE(mentions(notes, {"object 2 (counter) dropped: 100 % of it lies inside object 1 (counter)"})) << joined(notes);
  EXPECT_EQ(notes.size(), 2u) << joined(notes);
}

TEST(RoomModelCleanup, TheRigGetsFreeAirByTheLeastVolumeRemoved) {
  const Eigen::Vector3d rig(3.0, 2.0, 1.2);
  RoomModel model = room({6.0, 4.0, 2.7}, rig);
  model.objects = {
      box("cabinet", {3.0, 2.0, 0.9}, {6.0, 1.2, 1.8}),   // the rig in its middle: split along x
      box("table", {3.0, 2.9, 0.5}, {1.6, 0.6, 1.0}),     // top 0.2 m below the rig's height, 0.3 m aside
      box("lamp", {3.1, 1.0, 1.2}, {0.2, 0.3, 0.2}, 0.4)};  // 0.85 m away: untouched
  const auto notes = cleanUpRoomModel(model);
  ASSERT_EQ(model.objects.size(), 4u) << joined(notes);
  EXPECT_EQ(notes.size(), 1u) << joined(notes);
  // The cabinet in two: x 0..2.7 and 3.3..6, 0.6 x 1.2 x 1.8 = 1.296 m^3 gone (along z it
  // would be 4.32, along y 6.48).
  EXPECT_NEAR(model.objects[0].center_m.x(), 1.35, 1e-12);
  EXPECT_NEAR(model.objects[0].size_m.x(), 2.7, 1e-12);
  EXPECT_NEAR(model.objects[1].center_m.x(), 4.65, 1e-12);
  EXPECT_NEAR(model.objects[1].size_m.x(), 2.7, 1e-12);
  EXPECT_EQ(model.objects[1].label, "cabinet");
  EXPECT_TRUE(mentions(notes, {"object 0 (cabinet) split in two along its own x axis", "0.30 m of free air",
                               "(3, 2, 1.2) m", "1.3 of 13 m^3 removed"}))
      << joined(notes);
  // The table, flush with the cabinet at y = 2.6, is 0.6 m from the rig in y: untouched.
  EXPECT_EQ(model.objects[2].label, "table");
  EXPECT_EQ(model.objects[2].size_m, Eigen::Vector3d(1.6, 0.6, 1.0));
  EXPECT_EQ(model.objects[3].label, "lamp");
  for (const CuboidObject& object : model.objects) EXPECT_GE(distanceToCuboid(object, rig), 0.3 - 1e-12) << object.label;

  // An object wholly within the clearance goes, and says so.
  RoomModel desk = room({6.0, 4.0, 2.7}, rig);
  desk.objects = {box("cup", {3.1, 2.0, 1.3}, {0.1, 0.1, 0.1})};
  const auto cup_notes = cleanUpRoomModel(desk);
  EXPECT_TRUE(desk.objects.empty());
  ASSERT_EQ(cup_notes.size(), 1u);
  EXPECT_EQ(cup_notes[0], "object 0 (cup) dropped to keep 0.30 m of free air around the rig at (3, 2, 1.2) m: "
                          "nothing of it lies 0.30 m or more from the rig");
}

TEST(RoomModelCleanup, AnObjectNearTheRigIsCutOnTheSideThatCostsLeast) {
  const Eigen::Vector3d rig(1.8, 2.0, 1.2);
  RoomModel model = room({6.0, 4.0, 2.7}, rig);
  model.objects = {box("cupboard", {1.0, 2.0, 0.9}, {2.0, 1.0, 1.8}),    // rig 0.2 m from its +x end
                   box("table", {4.0, 2.0, 0.5}, {1.6, 0.8, 1.0})};      // 2.2 m off
  model.rig_position_m = rig;
  auto notes = cleanUpRoomModel(model);
  ASSERT_EQ(model.objects.size(), 2u) << joined(notes);
  // Along x 0.5 x 1 x 1.8 = 0.9 m^3 goes (along z 1.2, along y 2.16).
  EXPECT_NEAR(model.objects[0].center_m.x(), 0.75, 1e-12);
  EXPECT_NEAR(model.objects[0].size_m.x(), 1.5, 1e-12);
  EXPECT_TRUE(mentions(notes, {"object 0 (cupboard) cut back along its own x axis", "0.9 of 3.6 m^3 removed"})) << joined(notes);

  // A table whose top is 0.2 m below the rig loses its top 0.1 m (0.128 m^3), not a slot.
  RoomModel dining = room({6.0, 4.0, 2.7}, {3.0, 2.0, 1.2});
  dining.objects = {box("table", {3.0, 2.0, 0.5}, {1.6, 0.8, 1.0})};
  notes = cleanUpRoomModel(dining);
  ASSERT_EQ(dining.objects.size(), 1u);
  EXPECT_NEAR(dining.objects[0].size_m.z(), 0.9, 1e-12);
  EXPECT_NEAR(dining.objects[0].center_m.z(), 0.45, 1e-12);
  EXPECT_TRUE(mentions(notes, {"cut back along its own z axis", "0.128 of 1.28 m^3 removed"})) << joined(notes);

  // A turned cabinet holding the rig is cut in its own frame: same yaw, 0.3 m clear.
  RoomModel turned = room({6.0, 4.0, 2.7}, {3.0, 2.0, 1.2});
  turned.objects = {box("cabinet", {3.2, 2.1, 1.0}, {3.0, 0.8, 2.0}, 0.5)};
  notes = cleanUpRoomModel(turned);
  ASSERT_EQ(turned.objects.size(), 2u) << joined(notes);
  for (const CuboidObject& piece : turned.objects) {
    EXPECT_EQ(piece.yaw_rad, 0.5);
    EXPECT_NEAR(distanceToCuboid(piece, turned.rig_position_m), 0.3, 1e-12);
  }
}

TEST(RoomModelCleanup, ARigOutsideTheBoxIsReportedAndBadOptionsAreRefused) {
  RoomModel model = room({5.0, 4.0, 3.0}, {5.5, 2.0, 1.2});
  model.objects = {box("table", {5.0, 2.0, 0.5}, {1.0, 1.0, 1.0})};
  const auto notes = cleanUpRoomModel(model);
  EXPECT_TRUE(mentions(notes, {"the rig at (5.5, 2, 1.2) m is outside the room box [0, 5] x [0, 4] x [0, 3] m"})) << joined(notes);
  RoomModelCleanup bad;
  bad.rig_clearance_m = -0.1;
  expectInputError([&] { cleanUpRoomModel(model, bad); }, {"rig_clearance_m"});
  bad = {};
  bad.hidden_fraction = 0.0;
  expectInputError([&] { cleanUpRoomModel(model, bad); }, {"hidden_fraction"});
  model.objects[0].size_m.y() = 0.0;
  expectInputError([&] { cleanUpRoomModel(model); }, {"objects[0]"});
}

// A kitchen as the visual route fits one: a 6 x 4 x 2.7 m box; units flush against the
// walls, the floor, the ceiling and each other; an oven fitted inside the counter run; a
// radiator reaching through a wall; and a 6 m "cabinet" (the island and what stood on it
// seen as one) that holds the rig.
RoomModel fittedKitchen() {
  RoomModel k = room({6.0, 4.0, 2.7}, {3.0, 2.2, 1.2});
  k.surfaces["floor"].material = "tiles_ceramic";
  k.objects = {box("counter_run", {3.0, 0.3, 0.45}, {6.0, 0.6, 0.9}),
               box("wall_cabinets", {3.0, 0.175, 2.35}, {6.0, 0.35, 0.7}),
               box("fridge", {0.35, 3.65, 0.95}, {0.7, 0.7, 1.9}),
               box("tall_cupboard", {1.0, 3.7, 1.35}, {0.6, 0.6, 2.7}),
               box("shelf_unit", {1.65, 3.8, 1.0}, {0.7, 0.4, 2.0}),
               box("table", {5.0, 3.2, 0.375}, {1.6, 0.8, 0.75}),
               box("bench", {5.0, 3.8, 0.225}, {1.6, 0.4, 0.45}),
               box("oven", {2.0, 0.3, 0.45}, {0.6, 0.6, 0.9}),
               box("hood", {3.0, 0.25, 1.85}, {0.9, 0.5, 0.3}),
               box("radiator", {5.95, 1.2, 0.4}, {0.2, 0.6, 0.6}),
               box("chair", {3.6, 3.3, 0.45}, {0.45, 0.45, 0.9}, 0.3),
               box("bin", {5.85, 0.75, 0.3}, {0.3, 0.3, 0.6}),
               box("cabinet", {3.0, 2.2, 0.9}, {6.0, 1.2, 1.8})};
  return k;
}

SimulationSettings quickSettings() {
  SimulationSettings settings;
  settings.duration_s = 0.5;
  settings.image_source_order = 2;
  settings.rays.ray_count = 2000;
  settings.rays.threads = 2;
  return settings;
}

TEST(RoomModelCleanup, AFittedKitchenSimulatesFromTheRigOnceCleanedUp) {
  const MaterialLibrary library = MaterialLibrary::loadDefault();
  const Eigen::Vector3d source(3.0, 0.2, 1.2);  // above the counter, 2 m from the rig
  RoomModel kitchen = fittedKitchen();
  ASSERT_NEAR((source - kitchen.rig_position_m).norm(), 2.0, 1e-12);

  // As fitted: the free air among the flush units is free, the rig is not. (Crossing
  // parity on the same triangles refuses the last three points: rays graze the faces the
  // units share with the walls and each other.)
  const AcousticScene fitted = roomModelToScene(kitchen, library);
  for (const Eigen::Vector3d& air : {source, Eigen::Vector3d(4.25, 0.75, 1.75), Eigen::Vector3d(2.25, 3.25, 1.25),
                                     Eigen::Vector3d(3.75, 1.25, 2.25)}) {
    fitted.requireInside(air, "source");
  }
  // The box's 64.8 m^3 less the units' 21.80625 (the oven inside the counter run counted
  // once, the radiator only inside the wall).
  EXPECT_NEAR(fitted.volumeM3(), 42.99375, 1e-9);
  expectInputError([&] { simulateRoom(fitted, source, kitchen.rig_position_m, quickSettings()); },
                   {"listener (3, 2.2, 1.2) m is inside object 12 (cabinet)"});

  const auto notes = cleanUpRoomModel(kitchen);
  EXPECT_EQ(notes.size(), 3u) << joined(notes);
  EXPECT_TRUE(mentions(notes, {"object 9 (radiator) cut back to the room box: it reached 0.05 m through wall_x_max"}))
      << joined(notes);
  EXPECT_TRUE(mentions(notes, {"object 7 (oven) dropped: 100 % of it lies inside object 0 (counter_run)"})) << joined(notes);
  EXPECT_TRUE(mentions(notes, {"object 12 (cabinet) split in two along its own x axis"})) << joined(notes);
  ASSERT_EQ(kitchen.objects.size(), 13u);

  const AcousticScene cleaned = roomModelToScene(kitchen, library);
  EXPECT_NEAR(cleaned.volumeM3(), 42.99375 + 1.296, 1e-9);  // the slot cut for the rig
  const SimulationResult result = simulateRoom(cleaned, source, kitchen.rig_position_m, quickSettings());
  // The direct sound (through the slot cut for the rig) arrives after 2 m at the speed of
  // sound, the strongest arrival; the next, off the wall behind the source, 1.2 ms later.
  ASSERT_FALSE(result.paths.empty());
  EXPECT_EQ(result.paths[0].order, 0);
  EXPECT_NEAR(result.paths[0].delay_s, 2.0 / result.speed_of_sound_m_s, 1e-9);
  const std::vector<float>& w = result.impulse_response.channels.at(0);
  std::size_t peak = 0;
  for (std::size_t n = 0; n < w.size(); ++n) {
    if (std::abs(w[n]) > std::abs(w[peak])) peak = n;
  }
  EXPECT_GT(std::abs(w[peak]), 0.0f);
  EXPECT_NEAR(static_cast<double>(peak) / result.impulse_response.sample_rate_hz, 2.0 / result.speed_of_sound_m_s, 0.5e-3);
  // A closed room: no ray leaks through the flush and split units.
  EXPECT_EQ(result.stats.leaked_rays, 0u);
  EXPECT_GT(result.stats.sphere_detections, 0u);
}

// What drawing a room's clutter as cuboids does to its simulated decay: each cluttered
// room as the rig sees it (recesses, skirting, radiators, shelves and books, units, all as
// cuboids) and as the box of its main walls with its furniture, simulated from the rig to
// a source 2 m away at the rig's height (the first direction from 0.3 rad on, in 5 degree
// steps, with the source 0.5 m inside the box and 0.3 m from every surface of both
// models), accurate mode with its defaults, omni: T30 over 500 Hz-2 kHz of each. The
// figures in docs/visual-route.md ("The decay a model of a furnished room gives"):
//   ROOM_REVERB_CLUTTER_DECAY_REPORT=1 .ws/devel/lib/room_reverb/test_room_model_cleanup --gtest_filter='*Report*'
TEST(ClutteredRoomsDecayReport, DetailDrawnAsCuboids) {
  if (!std::getenv("ROOM_REVERB_CLUTTER_DECAY_REPORT")) GTEST_SKIP() << "set ROOM_REVERB_CLUTTER_DECAY_REPORT=1 for the report";
  const MaterialLibrary library = MaterialLibrary::loadDefault();
  SimulationSettings settings;
  settings.ambisonic_order = 0;
  settings.rays.threads = 2;
  const auto t30 = [](const SimulationResult& r) {
    const MetricsReport m = analyseImpulseResponse(r.impulse_response, 0, {});
    double sum = 0.0;
    for (std::size_t b = 3; b <= 5; ++b) sum += m.bands[b].t30_s.value_or(std::nan(""));
    return sum / 3.0;
  };
  for (const auto& [set, first] : {std::pair{ClutterSet::kDevelopment, 1}, std::pair{ClutterSet::kHeldOut, 201}}) {
    for (int index = first; index < first + 4; ++index) {
      const ClutteredRoom room = clutteredRoom(set, index);
      const AcousticScene scanned = roomModelToScene(room.scanned, library);
      const AcousticScene truth = roomModelToScene(room.truth, library);
      const Eigen::Vector3d rig = room.scanned.rig_position_m;
      std::optional<Eigen::Vector3d> source;
      for (int k = 0; k < 72 && !source; ++k) {
        const double a = 0.3 + k * M_PI / 36.0;
        const Eigen::Vector3d p = rig + 2.0 * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
        bool free = true;
        for (const AcousticScene* scene : {&scanned, &truth}) {
          free = free && scene->isInside(p) && scene->distanceToNearestSurface(p) > 0.3;
        }
        for (int axis = 0; axis < 2; ++axis) free = free && p[axis] > 0.5 && p[axis] < room.truth.size_m[axis] - 0.5;
        if (free) source = p;
      }
      ASSERT_TRUE(source) << room.name;
      const double detailed = t30(simulateRoom(scanned, *source, rig, settings));
      const double boxed = t30(simulateRoom(truth, *source, rig, settings));
      std::printf("[ measured ] %-16s T30 500 Hz-2 kHz: as seen %.3f s, box and furniture %.3f s (%+.0f %%)\n",
                  room.name.c_str(), detailed, boxed, 100.0 * (boxed / detailed - 1.0));
    }
  }
}
