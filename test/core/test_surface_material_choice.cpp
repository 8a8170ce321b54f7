// How the material step chooses once the classifier has voted: the runner-up of every
// face and object, the fallback of a close vote to the commonest material of the kind (the
// fallback: section of config/material_families.yaml), the user's override file, and the
// runner-up keys of room.yaml.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "room_reverb/common/error.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/material_families.h"
#include "room_reverb/vision/material_overrides.h"
#include "room_reverb/vision/surface_materials.h"
#include "shipped_materials.h"
#include "test_files.h"
#include "true_layout.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;
using room_reverb::test::writeFile;
using room_reverb::test::trueLayout;
using room_reverb::test::library;
using room_reverb::test::shippedFamilies;
using room_reverb::test::sourcePath;

namespace {

// The shipped rules with a fallback below half the vote, the threshold the tallies below
// are written for (a winner without a majority).
const MaterialFamilyTable& halfFamilies() {
  static const MaterialFamilyTable table = [] {
    MaterialFamilyTable half = shippedFamilies();
    half.fallback.min_confidence = 0.5;
    return half;
  }();
  return table;
}

// A vote over 2 m^2 with the given shares; what is left over is spread evenly over the
// families not named, so that no other family comes close.
MaterialVote voteOf(const std::map<TextureFamily, double>& shares) {
  MaterialVote vote;
  vote.area_m2 = 2.0;
  vote.patches = 8;
  double named = 0.0;
  for (const auto& [family, share] : shares) named += share;
  const double rest = (1.0 - named) / static_cast<double>(kTextureFamilyCount - static_cast<int>(shares.size()));
  for (int k = 0; k < kTextureFamilyCount; ++k) {
    const auto it = shares.find(textureFamilyAt(k));
    vote.votes[static_cast<std::size_t>(k)] = vote.area_m2 * (it != shares.end() ? it->second : rest);
  }
  return vote;
}

using F = TextureFamily;

struct MeetingRoom {
  CaptureScene scene;
  StereoCapture capture;
};

const MeetingRoom& meetingRoom() {
  static const MeetingRoom room = [] {
    MeetingRoom r;
    r.scene = loadCaptureScene(sourcePath("data/captures/mr.yaml"));
    r.scene.options.width = 1024;
    r.capture = renderCapture(r.scene.room, library(), r.scene.options);
    return r;
  }();
  return room;
}

const MaterialClassifier& shippedClassifier() {
  // The shipped one, or $ROOM_REVERB_MATERIAL_CLASSIFIER.
  static const MaterialClassifier classifier = MaterialClassifier::load(MaterialClassifier::defaultPath());
  return classifier;
}

std::string familyRows() {
  std::string rows = "families:\n";
  for (const TextureFamily family : allTextureFamilies()) {
    rows += "  " + toString(family) + ": {material: " + shippedFamilies().families.at(family).material + "}\n";
  }
  return rows;
}

}  // namespace

TEST(MaterialFallback, ShippedRulesCoverTheBoxFaces) {
  const MaterialFallback& fallback = shippedFamilies().fallback;
  EXPECT_DOUBLE_EQ(fallback.min_confidence, 0.40);
  ASSERT_EQ(fallback.rules.count(SurfacePlacement::kWall), 1u);
  ASSERT_EQ(fallback.rules.count(SurfacePlacement::kCeiling), 1u);
  ASSERT_EQ(fallback.rules.count(SurfacePlacement::kFloor), 1u);
  EXPECT_EQ(fallback.rules.count(SurfacePlacement::kObject), 0u);
  EXPECT_EQ(fallback.rules.at(SurfacePlacement::kWall).material, "plaster_smooth");
  EXPECT_EQ(fallback.rules.at(SurfacePlacement::kFloor).material, "linoleum_on_concrete");
  for (const auto& [placement, rule] : fallback.rules) EXPECT_TRUE(library().contains(rule.material)) << toString(placement);
}

TEST(MaterialFallback, ACloseWallVoteFallsBackToPlaster) {
  // 40 % brick, 35 % plaster: brick wins without a majority.
  const auto d = decideFromVote(voteOf({{F::kBrick, 0.40}, {F::kPlaster, 0.35}}), SurfacePlacement::kWall, halfFamilies());
  EXPECT_TRUE(d.seen);
  EXPECT_TRUE(d.fell_back);
  EXPECT_EQ(d.material, "plaster_smooth");
  EXPECT_EQ(d.family, F::kPlaster);
  EXPECT_NEAR(d.confidence, 0.35, 1e-12);
  // The runner-up is the close winner that was set aside.
  EXPECT_EQ(d.runner_up, "brick_bare");
  EXPECT_EQ(d.runner_up_family, F::kBrick);
  EXPECT_NEAR(d.runner_up_confidence, 0.40, 1e-12);
  EXPECT_NE(d.fallback_reason.find("brick (0.40)"), std::string::npos) << d.fallback_reason;
  EXPECT_NE(d.fallback_reason.find("min_confidence 0.50"), std::string::npos) << d.fallback_reason;
  EXPECT_NE(d.fallback_reason.find("commonest wall"), std::string::npos) << d.fallback_reason;
  EXPECT_FALSE(d.overridden);

  // The shipped threshold, 0.40, keeps a 45 % winner and sets a 33 % one aside.
  const auto kept = decideFromVote(voteOf({{F::kBrick, 0.45}, {F::kPlaster, 0.35}}), SurfacePlacement::kWall, shippedFamilies());
  EXPECT_FALSE(kept.fell_back);
  EXPECT_EQ(kept.material, "brick_bare");
  EXPECT_EQ(kept.runner_up, "plaster_smooth");
  const auto close = decideFromVote(voteOf({{F::kBrick, 0.33}, {F::kPlaster, 0.30}}), SurfacePlacement::kWall, shippedFamilies());
  EXPECT_TRUE(close.fell_back);
  EXPECT_EQ(close.material, "plaster_smooth");
  EXPECT_EQ(close.runner_up, "brick_bare");
}

TEST(MaterialFallback, ACeilingWithTilesAsRunnerUpGetsCeilingTiles) {
  const auto d = decideFromVote(voteOf({{F::kPlaster, 0.40}, {F::kTiles, 0.30}}), SurfacePlacement::kCeiling, halfFamilies());
  EXPECT_TRUE(d.fell_back);
  EXPECT_EQ(d.material, "acoustic_ceiling_tiles");
  EXPECT_NEAR(d.confidence, 0.30, 1e-12);
  EXPECT_EQ(d.runner_up, "plaster_smooth");
  EXPECT_NEAR(d.runner_up_confidence, 0.40, 1e-12);
  EXPECT_NE(d.fallback_reason.find("looks like tiles"), std::string::npos) << d.fallback_reason;

  // Tiles with too small a share: a plaster ceiling.
  const auto plain = decideFromVote(voteOf({{F::kBrick, 0.45}, {F::kPlaster, 0.30}, {F::kTiles, 0.10}}),
                                    SurfacePlacement::kCeiling, halfFamilies());
  EXPECT_TRUE(plain.fell_back);
  EXPECT_EQ(plain.material, "plaster_smooth");
  EXPECT_EQ(plain.runner_up, "brick_bare");
}

TEST(MaterialFallback, AFloorGoesByLookAmongFloorFamiliesElseLinoleum) {
  const auto wood = decideFromVote(voteOf({{F::kBrick, 0.45}, {F::kWood, 0.30}, {F::kCarpet, 0.10}}),
                                   SurfacePlacement::kFloor, halfFamilies());
  EXPECT_TRUE(wood.fell_back);
  EXPECT_EQ(wood.material, "wood_floor");
  EXPECT_NEAR(wood.confidence, 0.30, 1e-12);
  // A winner among the floor families keeps its family even below min_confidence.
  const auto carpet = decideFromVote(voteOf({{F::kCarpet, 0.45}, {F::kGlass, 0.40}}), SurfacePlacement::kFloor, halfFamilies());
  EXPECT_TRUE(carpet.fell_back);
  EXPECT_EQ(carpet.material, "carpet_on_concrete");
  // No floor family with min_share: the neutral default.
  const auto neutral = decideFromVote(voteOf({{F::kBrick, 0.45}, {F::kGlass, 0.40}, {F::kWood, 0.05}}),
                                      SurfacePlacement::kFloor, halfFamilies());
  EXPECT_TRUE(neutral.fell_back);
  EXPECT_EQ(neutral.material, "linoleum_on_concrete");
  EXPECT_EQ(neutral.family, F::kTiles);  // linoleum looks like tiles
  EXPECT_EQ(neutral.runner_up, "brick_bare");
}

TEST(MaterialFallback, AClearVoteAndObjectsKeepTheWinnerWithTheRunnerUp) {
  const auto clear = decideFromVote(voteOf({{F::kBrick, 0.80}, {F::kPlaster, 0.15}}), SurfacePlacement::kWall, halfFamilies());
  EXPECT_FALSE(clear.fell_back);
  EXPECT_TRUE(clear.fallback_reason.empty());
  EXPECT_EQ(clear.material, "brick_bare");
  EXPECT_NEAR(clear.confidence, 0.80, 1e-12);
  EXPECT_EQ(clear.runner_up, "plaster_smooth");
  EXPECT_NEAR(clear.runner_up_confidence, 0.15, 1e-12);
  // The runner-up's material is its family's at the placement.
  const auto floor = decideFromVote(voteOf({{F::kCarpet, 0.70}, {F::kWood, 0.25}}), SurfacePlacement::kFloor, halfFamilies());
  EXPECT_EQ(floor.runner_up, "wood_floor");
  // Objects have no rule: a close vote keeps its winner.
  const auto object = decideFromVote(voteOf({{F::kFabric, 0.30}, {F::kWood, 0.25}}), SurfacePlacement::kObject, halfFamilies());
  EXPECT_FALSE(object.fell_back);
  EXPECT_EQ(object.material, "fabric_upholstered_seat");
  EXPECT_EQ(object.runner_up, "wood_panel");
  // A unanimous vote has no runner-up.
  const auto unanimous = decideFromVote(voteOf({{F::kGlass, 1.0}}), SurfacePlacement::kWall, halfFamilies());
  EXPECT_TRUE(unanimous.runner_up.empty());
  EXPECT_DOUBLE_EQ(unanimous.runner_up_confidence, 0.0);
  EXPECT_DOUBLE_EQ(unanimous.confidence, 1.0);
  // A table without a fallback: section never falls back.
  const MaterialFamilyTable bare = parseMaterialFamilyTable(familyRows(), library(), "bare.yaml");
  EXPECT_TRUE(bare.fallback.rules.empty());
  const auto kept = decideFromVote(voteOf({{F::kBrick, 0.40}, {F::kPlaster, 0.35}}), SurfacePlacement::kWall, bare);
  EXPECT_FALSE(kept.fell_back);
  EXPECT_EQ(kept.material, "brick_bare");
  expectInputError([&] { decideFromVote(MaterialVote{}, SurfacePlacement::kWall, shippedFamilies()); }, {"positive area"});
}

TEST(MaterialFallback, BadFallbackSectionsAreInputErrors) {
  const std::string rows = familyRows();
  const auto parse = [&](const std::string& fallback) { parseMaterialFamilyTable(rows + fallback, library(), "table.yaml"); };
  EXPECT_NO_THROW(parse("fallback:\n  min_confidence: 0.4\n  wall: {material: sheetrock}\n"));
  expectInputError([&] { parse("fallback:\n  wall: {material: plaster_smooth}\n"); }, {"table.yaml", "fallback.min_confidence", "missing"});
  expectInputError([&] { parse("fallback:\n  min_confidence: 1.5\n"); }, {"fallback.min_confidence", "[0, 1]"});
  expectInputError([&] { parse("fallback:\n  min_confidence: 0.5\n  roof: {material: plaster_smooth}\n"); },
                   {"fallback.roof", "unknown key"});
  expectInputError([&] { parse("fallback:\n  min_confidence: 0.5\n  wall: {material: no_such}\n"); },
                   {"fallback.wall.material", "'no_such' is not a material"});
  expectInputError([&] { parse("fallback:\n  min_confidence: 0.5\n  wall: {by_look: [tiles], min_share: 0.2}\n"); },
                   {"fallback.wall.material", "missing"});
  expectInputError([&] { parse("fallback:\n  min_confidence: 0.5\n  floor: {material: linoleum_on_concrete, by_look: [wood]}\n"); },
                   {"fallback.floor.by_look", "go together"});
  expectInputError([&] { parse("fallback:\n  min_confidence: 0.5\n  floor: {material: linoleum_on_concrete, min_share: 0.2}\n"); },
                   {"fallback.floor.min_share", "go together"});
  expectInputError(
      [&] { parse("fallback:\n  min_confidence: 0.5\n  floor: {material: linoleum_on_concrete, by_look: [parquet], min_share: 0.2}\n"); },
      {"fallback.floor.by_look[0]", "unknown texture family 'parquet'"});
  expectInputError(
      [&] { parse("fallback:\n  min_confidence: 0.5\n  floor: {material: linoleum_on_concrete, by_look: [wood, wood], min_share: 0.2}\n"); },
      {"fallback.floor.by_look[1]", "listed twice"});
  expectInputError(
      [&] { parse("fallback:\n  min_confidence: 0.5\n  floor: {material: linoleum_on_concrete, by_look: [wood], min_share: -0.1}\n"); },
      {"fallback.floor.min_share", "[0, 1]"});
  expectInputError([&] { parse("fallback:\n  min_confidence: 0.5\n  wall: {material: plaster_smooth, colour: white}\n"); },
                   {"fallback.wall.colour", "unknown key"});
  expectInputError([&] { parse("fallbacks:\n  min_confidence: 0.5\n"); }, {"fallbacks", "unknown key"});
}

TEST(MaterialOverrides, AGoodFileReadsWithLibraryNames) {
  const MaterialOverrideFile file = parseMaterialOverrides(
      "surfaces: {floor: linoleum_on_concrete, wall_y_max: drywall}\n"
      "objects:\n  - {index: 3, material: wood_panel}\n  - {label: cabinet, material: door}\n",
      library(), "override.yaml");
  EXPECT_EQ(file.source, "override.yaml");
  ASSERT_EQ(file.surfaces.size(), 2u);
  EXPECT_EQ(file.surfaces.at("floor"), "linoleum_on_concrete");
  EXPECT_EQ(file.surfaces.at("wall_y_max"), "plasterboard_on_studs");  // the alias drywall
  ASSERT_EQ(file.objects.size(), 2u);
  EXPECT_TRUE(file.objects[0].by_index);
  EXPECT_EQ(file.objects[0].index, 3u);
  EXPECT_FALSE(file.objects[1].by_index);
  EXPECT_EQ(file.objects[1].label, "cabinet");
  EXPECT_EQ(file.objects[1].material, "door_wood");

  const RoomModel room = loadCaptureScene(sourcePath("data/captures/mr.yaml")).room;
  // Labels first, then indices: objects[4] is the cabinet, and an index entry overrules its label's.
  const MaterialOverrideFile both = parseMaterialOverrides(
      "objects:\n  - {index: 4, material: metal}\n  - {label: cabinet, material: door_wood}\n  - {label: loudspeaker, material: foam}\n",
      library(), "both.yaml");
  const std::vector<std::string> chosen = resolveMaterialOverrides(both, room);
  ASSERT_EQ(chosen.size(), 6u + room.objects.size());
  for (std::size_t f = 0; f < 6; ++f) EXPECT_TRUE(chosen[f].empty()) << f;
  EXPECT_EQ(chosen[6 + 0], "acoustic_foam");  // loudspeaker
  EXPECT_TRUE(chosen[6 + 1].empty());         // loudspeaker_stand: another label
  EXPECT_EQ(chosen[6 + 4], "metal");
  // An empty list and no surfaces: nothing to do.
  EXPECT_NO_THROW(parseMaterialOverrides("surfaces: {}\nobjects: []\n", library()));
}

TEST(MaterialOverrides, BadFilesAreOneLineErrorsNamingFileAndKey) {
  const auto parse = [](const std::string& text) { parseMaterialOverrides(text, library(), "override.yaml"); };
  expectInputError([&] { parse("surfaces: {flor: carpet}\n"); }, {"override.yaml", "surfaces.flor", "unknown surface"});
  expectInputError([&] { parse("surfaces: {floor: linolium}\n"); },
                   {"override.yaml", "surfaces.floor", "unknown material 'linolium'", "linoleum_on_concrete"});
  expectInputError([&] { parse("objects:\n  - {index: 1, material: velvet}\n"); },
                   {"override.yaml", "objects[0].material", "unknown material 'velvet'"});
  expectInputError([&] { parse("surfaces: {floor: [carpet\n"); }, {"override.yaml", "not valid YAML"});
  expectInputError([&] { parse("- floor: carpet\n"); }, {"override.yaml", "expected a YAML map"});
  expectInputError([&] { parse("surface: {floor: carpet}\n"); }, {"override.yaml", "surface", "unknown key"});
  expectInputError([&] { parse("objects: {index: 1, material: metal}\n"); }, {"override.yaml", "objects", "must be a list"});
  expectInputError([&] { parse("objects:\n  - {index: 1, label: table, material: metal}\n"); },
                   {"override.yaml", "objects[0]", "not both or neither"});
  expectInputError([&] { parse("objects:\n  - {material: metal}\n"); }, {"objects[0]", "not both or neither"});
  expectInputError([&] { parse("objects:\n  - {index: -1, material: metal}\n"); }, {"objects[0].index", "whole number"});
  expectInputError([&] { parse("objects:\n  - {index: 1.5, material: metal}\n"); }, {"objects[0].index", "whole number"});
  expectInputError([&] { parse("objects:\n  - {index: 1}\n"); }, {"objects[0].material", "missing"});
  expectInputError([&] { parse("objects:\n  - {index: 1, material: metal, colour: grey}\n"); },
                   {"objects[0].colour", "unknown key"});
  expectInputError([] { loadMaterialOverrides(sourcePath("config/no_such_override.yaml"), library()); },
                   {"no_such_override.yaml"});

  RoomModel room = loadCaptureScene(sourcePath("data/captures/mr.yaml")).room;
  const auto resolve = [&](const std::string& text) {
    resolveMaterialOverrides(parseMaterialOverrides(text, library(), "override.yaml"), room);
  };
  expectInputError([&] { resolve("objects:\n  - {index: 0, material: metal}\n  - {index: 5, material: metal}\n"); },
                   {"override.yaml", "objects[1].index", "5 is past the room's objects (0 to 4)"});
  expectInputError([&] { resolve("objects:\n  - {label: sofa, material: fabric_upholstered_seat}\n"); },
                   {"override.yaml", "objects[0].label", "no object is labelled 'sofa'", "cabinet", "whiteboard"});
  room.has_ceiling = false;
  expectInputError([&] { resolve("surfaces: {ceiling: plaster_smooth}\n"); }, {"override.yaml", "surfaces.ceiling", "no ceiling"});
}

TEST(SurfaceMaterials, OverridesRunnerUpsAndRoomYamlOnAGeneratedCapture) {
  const MeetingRoom& mr = meetingRoom();
  const std::string path = writeFile("mr_override.yaml",
                                     "surfaces: {floor: linoleum_on_concrete, wall_x_max: brick_bare}\n"
                                     "objects:\n  - {label: table, material: metal}\n  - {index: 4, material: door_wood}\n");
  RoomLayout plain = trueLayout(mr.scene.room);
  const auto found = assignSurfaceMaterials(plain, mr.capture.top.color, mr.scene.options.baseline_m, shippedClassifier(),
                                            shippedFamilies());
  RoomLayout corrected = trueLayout(mr.scene.room);
  SurfaceMaterialOptions options;
  options.override_file = path;
  const auto decisions = assignSurfaceMaterials(corrected, mr.capture.top.color, mr.scene.options.baseline_m,
                                                shippedClassifier(), shippedFamilies(), options);
  ASSERT_EQ(decisions.size(), found.size());
  const RoomModel& model = corrected.model;
  EXPECT_EQ(model.surfaces.at("floor").material, "linoleum_on_concrete");
  EXPECT_DOUBLE_EQ(model.surfaces.at("floor").confidence, 1.0);
  EXPECT_TRUE(model.surfaces.at("floor").runner_up.empty());
  EXPECT_EQ(model.surfaces.at("wall_x_max").material, "brick_bare");
  EXPECT_EQ(model.objects[2].material, "metal");  // the table
  EXPECT_DOUBLE_EQ(model.objects[2].confidence, 1.0);
  EXPECT_EQ(model.objects[4].material, "door_wood");  // the cabinet
  for (std::size_t i = 0; i < decisions.size(); ++i) {
    const SurfaceMaterialDecision& d = decisions[i];
    const bool named = d.name == "floor" || d.name == "wall_x_max" || i == 6 + 2 || i == 6 + 4;
    EXPECT_EQ(d.overridden, named) << d.name;
    if (named) {
      // What the route found stays in the decision, as it was without the file.
      EXPECT_EQ(d.found_material, found[i].material) << d.name;
      EXPECT_DOUBLE_EQ(d.found_confidence, found[i].confidence) << d.name;
      EXPECT_DOUBLE_EQ(d.confidence, 1.0) << d.name;
    } else {
      EXPECT_EQ(d.material, found[i].material) << d.name;
      EXPECT_DOUBLE_EQ(d.confidence, found[i].confidence) << d.name;
    }
  }
  // Every seen face and object of the plain run carries its runner-up into the model.
  int runner_ups = 0;
  for (std::size_t f = 0; f < 6; ++f) {
    const SurfaceAssignment& surface = plain.model.surfaces.at(kRoomSurfaceNames[f]);
    EXPECT_EQ(surface.runner_up, found[f].runner_up) << kRoomSurfaceNames[f];
    EXPECT_DOUBLE_EQ(surface.runner_up_confidence, found[f].runner_up_confidence) << kRoomSurfaceNames[f];
    if (found[f].seen && !found[f].runner_up.empty()) {
      ++runner_ups;
      EXPECT_TRUE(library().contains(surface.runner_up)) << surface.runner_up;
      EXPECT_GT(surface.runner_up_confidence, 0.0);
      // Second to the chosen family's share, unless a fallback set a close winner aside.
      if (!found[f].fell_back) {
        EXPECT_LE(surface.runner_up_confidence, found[f].confidence + 1e-12) << kRoomSurfaceNames[f];
      }
      EXPECT_NE(textureFamilyFor(surface.runner_up).family, textureFamilyFor(surface.material).family);
    }
  }
  EXPECT_GE(runner_ups, 4);
  for (std::size_t k = 0; k < plain.model.objects.size(); ++k) {
    EXPECT_EQ(plain.model.objects[k].runner_up, found[6 + k].runner_up) << k;
  }

  // room.yaml keeps the runner-up keys and reads back into a simulable scene.
  const std::string yaml = roomModelToYaml(plain.model);
  EXPECT_NE(yaml.find("runner_up: "), std::string::npos) << yaml;
  const RoomModel read = parseRoomModel(yaml);
  for (const auto& [name, surface] : plain.model.surfaces) {
    EXPECT_EQ(read.surfaces.at(name).runner_up, surface.runner_up) << name;
    EXPECT_DOUBLE_EQ(read.surfaces.at(name).runner_up_confidence, surface.runner_up_confidence) << name;
  }
  for (std::size_t k = 0; k < read.objects.size(); ++k) {
    EXPECT_EQ(read.objects[k].runner_up, plain.model.objects[k].runner_up) << k;
  }
  EXPECT_NO_THROW(roomModelToScene(read, library()));
  EXPECT_NO_THROW(roomModelToScene(parseRoomModel(roomModelToYaml(model)), library()));

  // A label the fitted room lacks fails before anything is assigned.
  const std::string bad = writeFile("mr_override_bad.yaml", "objects:\n  - {label: sofa, material: fabric_upholstered_seat}\n");
  options.override_file = bad;
  RoomLayout untouched = trueLayout(mr.scene.room);
  expectInputError([&] {
    assignSurfaceMaterials(untouched, mr.capture.top.color, mr.scene.options.baseline_m, shippedClassifier(), shippedFamilies(), options);
  }, {"mr_override_bad.yaml", "objects[0].label", "sofa"});
  EXPECT_TRUE(untouched.model.surfaces.at("floor").material.empty());
}

TEST(RoomModelRunnerUp, OptionalKeysAreReadCheckedAndIgnoredBySimulation) {
  const std::string base =
      "room_box: {size_m: [4, 3, 2.5]}\nsurfaces:\n"
      "  ceiling: {material: plaster_smooth}\n  wall_x_min: {material: plaster_smooth}\n"
      "  wall_x_max: {material: plaster_smooth}\n  wall_y_min: {material: plaster_smooth}\n"
      "  wall_y_max: {material: plaster_smooth}\n";
  const RoomModel model = parseRoomModel(base +
                                         "  floor: {material: carpet_on_concrete, confidence: 0.4, runner_up: wood_floor, "
                                         "runner_up_confidence: 0.3}\nobjects:\n  - {label: table, material: wood_panel, "
                                         "center_m: [2, 1.5, 0.4], size_m: [1, 1, 0.8], runner_up: metal}\n");
  EXPECT_EQ(model.surfaces.at("floor").runner_up, "wood_floor");
  EXPECT_DOUBLE_EQ(model.surfaces.at("floor").runner_up_confidence, 0.3);
  EXPECT_TRUE(model.surfaces.at("ceiling").runner_up.empty());
  EXPECT_EQ(model.objects[0].runner_up, "metal");
  EXPECT_DOUBLE_EQ(model.objects[0].runner_up_confidence, 0.0);
  // Written back with the same keys, and only where there is a runner-up.
  const std::string yaml = roomModelToYaml(model);
  EXPECT_NE(yaml.find("floor: {material: carpet_on_concrete, confidence: 0.4, runner_up: wood_floor, runner_up_confidence: 0.3}"),
            std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("ceiling: {material: plaster_smooth, confidence: 1}"), std::string::npos) << yaml;
  // The runner-up is not simulated: a name the library lacks is no error there.
  RoomModel odd = model;
  odd.surfaces["floor"].runner_up = "no_such_material";
  EXPECT_NO_THROW(roomModelToScene(odd, library()));

  expectInputError([&] { parseRoomModel(base + "  floor: {material: carpet, runner_up: wood, runner_up_confidence: 1.5}\n"); },
                   {"surfaces.floor.runner_up_confidence", "[0, 1]"});
  expectInputError([&] { parseRoomModel(base + "  floor: {material: carpet, runner_up_confidence: 0.2}\n"); },
                   {"surfaces.floor.runner_up_confidence", "without runner_up"});
}
