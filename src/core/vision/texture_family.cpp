#include "room_reverb/vision/texture_family.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace room_reverb::core {
namespace {

using F = TextureFamily;

// Every material of config/materials.yaml, by what the surface looks like (its
// description there), not by how it sounds: painted brick is still brick courses, an
// audience is clothes (fabric), a whiteboard is a flat pale panel (plaster). A material
// added to the library without a row here still gets a family from the keywords below;
// test_capture_generator checks that none falls through to the default.
constexpr std::array<std::pair<const char*, F>, 62> kLibraryFamilies = {{
    {"transparent", F::kOpening},           {"acoustic_ceiling_tiles", F::kTiles},
    {"brick_bare", F::kBrick},              {"brick_painted", F::kBrick},
    {"concrete_block_coarse", F::kConcrete}, {"concrete_block_painted", F::kConcrete},
    {"curtain_heavy", F::kFabric},          {"fiber_glass_insulation", F::kFoam},
    {"glass_thin", F::kGlass},              {"glass_thick", F::kGlass},
    {"grass", F::kNatural},                 {"linoleum_on_concrete", F::kTiles},
    {"marble", F::kTiles},                  {"metal", F::kMetal},
    {"parquet_on_concrete", F::kWood},      {"plaster_rough", F::kPlaster},
    {"plaster_smooth", F::kPlaster},        {"plywood_panel", F::kWood},
    {"polished_concrete_or_tile", F::kConcrete}, {"sheetrock", F::kPlaster},
    {"water_or_ice_surface", F::kGlass},    {"wood_ceiling", F::kWood},
    {"wood_panel", F::kWood},               {"uniform", F::kPlaster},
    {"generic", F::kPlaster},               {"brick", F::kBrick},
    {"concrete", F::kConcrete},             {"ceramic", F::kTiles},
    {"gravel", F::kNatural},                {"carpet", F::kCarpet},
    {"glass", F::kGlass},                   {"plaster", F::kPlaster},
    {"wood", F::kWood},                     {"steam_audio_metal", F::kMetal},
    {"rock", F::kNatural},                  {"mat_CR2_concrete", F::kConcrete},
    {"mat_CR2_windows", F::kGlass},         {"mat_CR2_ceiling", F::kPlaster},
    {"mat_CR2_plaster", F::kPlaster},       {"mat_CR2_floor", F::kTiles},
    {"carpet_on_concrete", F::kCarpet},     {"carpet_thick", F::kCarpet},
    {"curtain_light", F::kFabric},          {"fabric_upholstered_seat", F::kFabric},
    {"audience_seated", F::kFabric},        {"people", F::kFabric},
    {"chair_wooden", F::kWood},             {"wood_floor", F::kWood},
    {"tiles_ceramic", F::kTiles},           {"glass_window", F::kGlass},
    {"glass_double_glazing", F::kGlass},    {"door_wood", F::kWood},
    {"whiteboard", F::kPlaster},            {"bookshelf_with_books", F::kWood},
    {"acoustic_foam", F::kFoam},            {"mineral_wool_panel", F::kFoam},
    {"fabric_wall_panel", F::kFabric},      {"concrete_painted", F::kConcrete},
    {"concrete_unpainted", F::kConcrete},   {"plasterboard_on_studs", F::kPlaster},
    {"window_blinds", F::kFabric},          {"open_window", F::kOpening},
}};

// For names outside the table (inline materials of a scene): the first keyword found in
// the lower-cased name decides. Order matters where words combine ("glass_wool" is foam,
// "carpet_on_concrete" is carpet): the more specific look comes first.
constexpr std::array<std::pair<const char*, F>, 36> kKeywordFamilies = {{
    {"open", F::kOpening},    {"transparent", F::kOpening}, {"foam", F::kFoam},
    {"wool", F::kFoam},       {"insulation", F::kFoam},     {"carpet", F::kCarpet},
    {"rug", F::kCarpet},      {"curtain", F::kFabric},      {"drape", F::kFabric},
    {"fabric", F::kFabric},   {"textile", F::kFabric},      {"upholster", F::kFabric},
    {"seat", F::kFabric},     {"people", F::kFabric},       {"audience", F::kFabric},
    {"blind", F::kFabric},    {"brick", F::kBrick},         {"glass", F::kGlass},
    {"window", F::kGlass},    {"water", F::kGlass},         {"tile", F::kTiles},
    {"ceramic", F::kTiles},   {"marble", F::kTiles},        {"linoleum", F::kTiles},
    {"wood", F::kWood},       {"parquet", F::kWood},        {"plywood", F::kWood},
    {"timber", F::kWood},     {"oak", F::kWood},            {"pine", F::kWood},
    {"concrete", F::kConcrete},   {"metal", F::kMetal},
    {"steel", F::kMetal},     {"grass", F::kNatural},       {"gravel", F::kNatural},
    {"rock", F::kNatural},
}};

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

}  // namespace

TextureFamilyChoice textureFamilyFor(const std::string& material_name) {
  for (const auto& [name, family] : kLibraryFamilies) {
    if (material_name == name) return {family, TextureFamilySource::kTable};
  }
  const std::string lower = lowerCase(material_name);
  for (const auto& [keyword, family] : kKeywordFamilies) {
    if (lower.find(keyword) != std::string::npos) return {family, TextureFamilySource::kKeyword};
  }
  // Plaster, plasterboard, paint and anything unnamed: the commonest indoor finish.
  return {F::kPlaster, TextureFamilySource::kDefault};
}

std::string toString(TextureFamily family) {
  switch (family) {
    case F::kPlaster: return "plaster";
    case F::kBrick: return "brick";
    case F::kWood: return "wood";
    case F::kCarpet: return "carpet";
    case F::kTiles: return "tiles";
    case F::kGlass: return "glass";
    case F::kFabric: return "fabric";
    case F::kConcrete: return "concrete";
    case F::kMetal: return "metal";
    case F::kFoam: return "foam";
    case F::kNatural: return "natural";
    case F::kOpening: return "opening";
  }
  return "plaster";
}

std::vector<TextureFamily> allTextureFamilies() {
  return {F::kPlaster, F::kBrick, F::kWood,  F::kCarpet, F::kTiles,   F::kGlass,
          F::kFabric,  F::kConcrete, F::kMetal, F::kFoam, F::kNatural, F::kOpening};
}

}  // namespace room_reverb::core
