#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "test_files.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/common/error.h"

using namespace room_reverb::core;
namespace fs = std::filesystem;

namespace {

using room_reverb::test::expectInputError;
using room_reverb::test::tempPath;
using room_reverb::test::writeFile;

const std::string kLibraryPath = std::string(ROOM_REVERB_SOURCE_DIR) + "/config/materials.yaml";

const char* const kBands = "bands_hz: [63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000]\n";

// A small valid library; `absorption` replaces the first material's absorption list and
// `extra` is appended to the file.
std::string smallLibrary(
    const std::string& absorption = "[0.1, 0.1, 0.1, 0.1, 0.2, 0.2, 0.2, 0.3, 0.3]",
    const std::string& extra = "") {
  return std::string(kBands) +
         "materials:\n"
         "  wall:\n"
         "    description: \"test wall\"\n"
         "    absorption: " +
         absorption +
         "\n"
         "    scattering: [0.05, 0.05, 0.05, 0.05, 0.05, 0.05, 0.05, 0.05, 0.05]\n"
         "    source: \"unit test\"\n"
         "  floor:\n"
         "    description: \"test floor\"\n"
         "    absorption: [0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02]\n"
         "    scattering: [0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1]\n"
         "    source: \"unit test\"\n" +
         extra;
}

void expectLoadError(const std::string& name, const std::string& text,
                     const std::vector<std::string>& fragments) {
  const std::string path = writeFile(name, text);
  std::vector<std::string> expected = fragments;
  expected.push_back(path);  // every message names the file
  expectInputError([&] { MaterialLibrary::load(path); }, expected);
}

// Numbers of a flow list "key: [a, b, ...]" on the first line containing `key` after the
// line `  <material>:` in the real library file. Read as text so the test does not need
// yaml-cpp, which the core library keeps private.
std::vector<double> listAfter(const std::string& material, const std::string& key) {
  std::ifstream file(kLibraryPath);
  std::string line;
  bool inside = material.empty();
  while (std::getline(file, line)) {
    if (!inside) {
      inside = line == "  " + material + ":";
      continue;
    }
    const auto at = line.find(key + ": [");
    if (at == std::string::npos) continue;
    std::string numbers = line.substr(line.find('[', at) + 1);
    numbers = numbers.substr(0, numbers.find(']'));
    for (char& ch : numbers) {
      if (ch == ',') ch = ' ';
    }
    std::istringstream in(numbers);
    std::vector<double> values;
    for (double value; in >> value;) values.push_back(value);
    return values;
  }
  return {};
}

}  // namespace

TEST(MaterialLibrary, LoadsTheProjectLibrary) {
  const MaterialLibrary library = MaterialLibrary::load(kLibraryPath);
  EXPECT_GE(library.size(), 30u);
  const std::vector<std::string> names = library.names();
  EXPECT_EQ(names.size(), library.size());
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  for (const std::string& name : names) {
    const AcousticMaterial& material = library.get(name);
    EXPECT_EQ(material.name, name);
    EXPECT_FALSE(material.source.empty()) << name;
    EXPECT_NO_THROW(validateMaterial(material)) << name;
  }
  // Aliases resolve but are not listed as materials.
  EXPECT_TRUE(library.contains("drywall"));
  EXPECT_EQ(std::count(names.begin(), names.end(), "drywall"), 0);
}

TEST(MaterialLibrary, HasEveryResonanceAudioMaterial) {
  const MaterialLibrary library = MaterialLibrary::load(kLibraryPath);
  for (const char* name : {"transparent",
                           "acoustic_ceiling_tiles",
                           "brick_bare",
                           "brick_painted",
                           "concrete_block_coarse",
                           "concrete_block_painted",
                           "curtain_heavy",
                           "fiber_glass_insulation",
                           "glass_thin",
                           "glass_thick",
                           "grass",
                           "linoleum_on_concrete",
                           "marble",
                           "metal",
                           "parquet_on_concrete",
                           "plaster_rough",
                           "plaster_smooth",
                           "plywood_panel",
                           "polished_concrete_or_tile",
                           "sheetrock",
                           "water_or_ice_surface",
                           "wood_ceiling",
                           "wood_panel",
                           "uniform"}) {
    EXPECT_TRUE(library.contains(name)) << name;
  }
  const AcousticMaterial& transparent = library.get("transparent");
  for (double a : transparent.absorption) EXPECT_EQ(a, 1.0);
  for (double a : library.get("uniform").absorption) EXPECT_EQ(a, 0.5);
}

TEST(MaterialLibrary, HasEverySteamAudioPreset) {
  const MaterialLibrary library = MaterialLibrary::load(kLibraryPath);
  for (const std::string preset : {"generic", "brick", "concrete", "ceramic", "gravel", "carpet",
                                   "glass", "plaster", "wood", "rock"}) {
    EXPECT_TRUE(library.contains(preset)) << preset;
    // Every preset also answers to its prefixed name.
    ASSERT_TRUE(library.contains("steam_audio_" + preset)) << preset;
    EXPECT_EQ(&library.get("steam_audio_" + preset), &library.get(preset));
  }
  // Steam Audio's metal is stored under its prefixed name: "metal" is Resonance Audio's.
  EXPECT_TRUE(library.contains("steam_audio_metal"));
  EXPECT_EQ(library.get("steam_audio_default").name, "generic");
}

TEST(MaterialLibrary, HasTheBrasCr2MaterialsUnderBothNames) {
  const MaterialLibrary library = MaterialLibrary::load(kLibraryPath);
  for (const std::string surface : {"concrete", "windows", "ceiling", "plaster", "floor"}) {
    const std::string key = "mat_CR2_" + surface;
    const std::string alias = "mat_scene09_" + surface;
    ASSERT_TRUE(library.contains(key)) << key;
    ASSERT_TRUE(library.contains(alias)) << alias;
    EXPECT_EQ(library.get(alias).name, key);
    EXPECT_EQ(&library.get(alias), &library.get(key));
  }
}

TEST(MaterialLibrary, Cr2OctavesAreMeansOfTheThirdOctaveData) {
  const MaterialLibrary library = MaterialLibrary::load(kLibraryPath);
  const std::vector<double> centers = listAfter("", "third_octave_centers_hz");
  ASSERT_EQ(centers.size(), 31u);
  // Octave j (63 Hz ... 16 kHz) averages the thirds 50/63/80 Hz ... 12.5/16/20 kHz, which
  // start at index 4 of the 20 Hz ... 20 kHz list.
  ASSERT_EQ(centers[4], 50.0);
  ASSERT_EQ(centers[17], 1000.0);

  const std::vector<double> concrete = listAfter("mat_CR2_concrete", "absorption_third_octave");
  ASSERT_EQ(concrete.size(), 31u);
  const double expected_1k = (concrete[16] + concrete[17] + concrete[18]) / 3.0;  // 800/1000/1250
  EXPECT_NEAR(library.get("mat_CR2_concrete").absorption[4], expected_1k, 0.0005 + 1e-12);
  EXPECT_NEAR(library.get("mat_scene09_concrete").absorption[4], 0.058, 1e-12);

  for (const std::string surface : {"concrete", "windows", "ceiling", "plaster", "floor"}) {
    const AcousticMaterial& material = library.get("mat_CR2_" + surface);
    const std::vector<double> absorption = listAfter(material.name, "absorption_third_octave");
    const std::vector<double> scattering = listAfter(material.name, "scattering_third_octave");
    ASSERT_EQ(absorption.size(), 31u) << surface;
    ASSERT_EQ(scattering.size(), 31u) << surface;
    for (int band = 0; band < kOctaveBandCount; ++band) {
      const std::size_t first = 4 + 3 * static_cast<std::size_t>(band);
      const double mean_a =
          (absorption[first] + absorption[first + 1] + absorption[first + 2]) / 3.0;
      const double mean_s =
          (scattering[first] + scattering[first + 1] + scattering[first + 2]) / 3.0;
      // The library rounds the means to three decimals.
      EXPECT_NEAR(material.absorption[static_cast<std::size_t>(band)], mean_a, 0.0005 + 1e-12)
          << surface << " band " << band;
      EXPECT_NEAR(material.scattering[static_cast<std::size_t>(band)], mean_s, 0.0005 + 1e-12)
          << surface << " band " << band;
    }
  }
}

TEST(MaterialLibrary, UnknownNamesSuggestCloseOnes) {
  const MaterialLibrary library = MaterialLibrary::load(kLibraryPath);
  expectInputError([&] { library.get("concret"); }, {"unknown material 'concret'", "concrete"});
  expectInputError([&] { library.get("mat_scene9_floor"); }, {"mat_scene09_floor"});
  expectInputError([&] { library.get("Sheetrock"); }, {"sheetrock"});
  // A shared word is enough to be suggested.
  expectInputError([&] { library.get("office_wall_panel"); }, {"fabric_wall_panel"});
  expectInputError([&] { library.get("qqqqqqqq"); }, {"unknown material 'qqqqqqqq'"});
  // At most five suggestions.
  try {
    library.get("glas");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("glass"), std::string::npos) << message;
    EXPECT_LE(std::count(message.begin(), message.end(), ','), 4) << message;
  }
}

TEST(MaterialLibrary, DefaultPathFollowsTheEnvironment) {
  const char* previous = std::getenv("ROOM_REVERB_MATERIALS");
  const std::string saved = previous ? previous : "";

  ::unsetenv("ROOM_REVERB_MATERIALS");
  EXPECT_EQ(MaterialLibrary::defaultPath(), kLibraryPath);
  EXPECT_EQ(MaterialLibrary::loadDefault().size(), MaterialLibrary::load(kLibraryPath).size());

  const std::string small = writeFile("env_library.yaml", smallLibrary());
  ::setenv("ROOM_REVERB_MATERIALS", small.c_str(), 1);
  EXPECT_EQ(MaterialLibrary::defaultPath(), small);
  EXPECT_EQ(MaterialLibrary::loadDefault().size(), 2u);

  if (previous) {
    ::setenv("ROOM_REVERB_MATERIALS", saved.c_str(), 1);
  } else {
    ::unsetenv("ROOM_REVERB_MATERIALS");
  }
}

TEST(MaterialLibrary, LoadsASmallLibrary) {
  const MaterialLibrary library = MaterialLibrary::load(
      writeFile("small.yaml", smallLibrary("[0.1, 0.1, 0.1, 0.1, 0.2, 0.2, 0.2, 0.3, 0.3]",
                                           "aliases:\n  partition: wall\n")));
  EXPECT_EQ(library.names(), (std::vector<std::string>{"floor", "wall"}));
  EXPECT_DOUBLE_EQ(library.get("partition").absorption[8], 0.3);
  EXPECT_EQ(library.get("wall").source, "unit test");
}

TEST(MaterialLibrary, RejectsBadFiles) {
  expectInputError([] { MaterialLibrary::load("/nonexistent/materials.yaml"); },
                   {"/nonexistent/materials.yaml", "no such file"});
  expectLoadError("malformed.yaml", smallLibrary() + "aliases: [unclosed\n", {"malformed YAML"});
  expectLoadError("too_big.yaml", smallLibrary("[0.1, 0.1, 0.1, 0.1, 1.5, 0.2, 0.2, 0.3, 0.3]"),
                  {"'wall'", "absorption", "1000 Hz", "1.5", "[0, 1]"});
  expectLoadError("negative.yaml", smallLibrary("[-0.1, 0.1, 0.1, 0.1, 0.2, 0.2, 0.2, 0.3, 0.3]"),
                  {"'wall'", "absorption", "63 Hz", "-0.1"});
  expectLoadError("nan.yaml", smallLibrary("[0.1, 0.1, .nan, 0.1, 0.2, 0.2, 0.2, 0.3, 0.3]"),
                  {"'wall'", "absorption", "250 Hz", "finite"});
  expectLoadError("eight.yaml", smallLibrary("[0.1, 0.1, 0.1, 0.1, 0.2, 0.2, 0.2, 0.3]"),
                  {"'wall'", "absorption", "8 values", "expected 9"});
  expectLoadError("word.yaml", smallLibrary("[0.1, 0.1, 0.1, 0.1, high, 0.2, 0.2, 0.3, 0.3]"),
                  {"'wall'", "absorption", "not a number"});
  expectLoadError("alias.yaml", smallLibrary() + "aliases:\n  door: door_wood\n",
                  {"alias 'door'", "unknown material 'door_wood'"});
  expectLoadError("alias_shadow.yaml", smallLibrary() + "aliases:\n  wall: floor\n",
                  {"alias 'wall'", "also a material"});
  expectLoadError("duplicate.yaml",
                  smallLibrary() +
                      "  wall:\n    description: \"again\"\n"
                      "    absorption: [0, 0, 0, 0, 0, 0, 0, 0, 0]\n"
                      "    scattering: [0, 0, 0, 0, 0, 0, 0, 0, 0]\n    source: \"x\"\n",
                  {"'wall'", "defined twice"});
  expectLoadError("no_source.yaml",
                  std::string(kBands) +
                      "materials:\n  wall:\n    description: \"d\"\n"
                      "    absorption: [0, 0, 0, 0, 0, 0, 0, 0, 0]\n"
                      "    scattering: [0, 0, 0, 0, 0, 0, 0, 0, 0]\n",
                  {"'wall'", "source"});
  expectLoadError("bands.yaml",
                  "bands_hz: [125, 250, 500, 1000, 2000, 4000, 8000, 16000, 20000]\n" +
                      smallLibrary().substr(std::string(kBands).size()),
                  {"bands_hz"});
  expectLoadError("no_bands.yaml", smallLibrary().substr(std::string(kBands).size()), {"bands_hz"});
  expectLoadError("no_materials.yaml", std::string(kBands), {"materials"});
  expectLoadError("list.yaml", "- just\n- a list\n", {"mapping"});
  expectLoadError("list_key.yaml", std::string(kBands) + "materials:\n  ? [a, b]\n  : x\n",
                  {"unexpected content"});
}

TEST(MaterialLibrary, AddValidatesAndAliasesResolve) {
  MaterialLibrary library;
  AcousticMaterial panel;
  panel.name = "panel";
  panel.absorption.fill(0.3);
  panel.scattering.fill(0.1);
  library.add(panel);
  EXPECT_TRUE(library.contains("panel"));

  AcousticMaterial bad = panel;
  bad.name = "bad";
  bad.scattering[3] = std::numeric_limits<double>::infinity();
  expectInputError([&] { library.add(bad); }, {"'bad'", "scattering", "500 Hz"});
  EXPECT_FALSE(library.contains("bad"));
  bad.scattering[3] = 0.1;
  bad.absorption[0] = 1.0000001;
  expectInputError([&] { validateMaterial(bad); }, {"'bad'", "absorption", "63 Hz"});

  library.addAlias("board", "panel");
  library.addAlias("plank", "board");  // through an alias, ends at the material
  EXPECT_EQ(library.get("plank").name, "panel");
  expectInputError([&] { library.addAlias("x", "missing"); }, {"unknown material 'missing'"});
  expectInputError([&] { library.addAlias("panel", "panel"); }, {"already a material"});
  EXPECT_EQ(library.names(), std::vector<std::string>{"panel"});

  // Replacing keeps one entry; a material named like an alias takes the name over.
  panel.absorption.fill(0.4);
  library.add(panel);
  EXPECT_EQ(library.size(), 1u);
  EXPECT_DOUBLE_EQ(library.get("board").absorption[0], 0.4);
  AcousticMaterial board = panel;
  board.name = "board";
  board.absorption.fill(0.9);
  library.add(board);
  EXPECT_DOUBLE_EQ(library.get("board").absorption[0], 0.9);
}
