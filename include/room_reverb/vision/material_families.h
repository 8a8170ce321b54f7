#pragma once
// Which library material a surface gets once its texture family is known
// (config/material_families.yaml). The classifier tells families apart, not materials:
// two plasters look alike. Each family names a representative material of the library,
// optionally another one by where the surface is (wooden floors are parquet, tiled
// ceilings are acoustic tiles, fabric on furniture is upholstery).
//
// The table also says what a seen face falls back to when the classifier's vote is too
// close to call (the fallback: section): the commonest material of its placement, or the
// material of a family that still has a fair share of the vote among those the placement
// is usually made of (a ceiling of tiles, a floor of wood or carpet).
#include <map>
#include <string>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/vision/texture_family.h"

namespace room_reverb::core {

enum class SurfacePlacement { kFloor, kCeiling, kWall, kObject };

struct FamilyMaterials {
  std::string material;                               // the representative
  std::map<SurfacePlacement, std::string> placement;  // overrides by placement
};

// The fallback rule of one placement.
struct PlacementFallback {
  std::string material;                // the placement's commonest material (a library name)
  std::vector<TextureFamily> by_look;  // families the placement is commonly made of
  // The best of by_look is taken (its material at this placement) when it holds at least
  // this share of the area-weighted vote; below it, `material`.
  double min_share = 0.0;
};

struct MaterialFallback {
  // A seen face whose winning family holds less than this share of its vote falls back;
  // 0 never does.
  double min_confidence = 0.0;
  // Placements without a rule keep the winning family however close the vote.
  std::map<SurfacePlacement, PlacementFallback> rules;
};

struct MaterialFamilyTable {
  std::map<TextureFamily, FamilyMaterials> families;  // every family
  // What a surface the camera did not see well enough is taken to be: the commonest
  // indoor finish unless the file says otherwise.
  TextureFamily unseen_family = TextureFamily::kPlaster;
  // Empty (never falls back) when the file has no fallback: section.
  MaterialFallback fallback;

  // The material for a family at a placement (the override, else the representative).
  const std::string& materialFor(TextureFamily family, SurfacePlacement placement) const;
};

// Parses the table (format: config/material_families.yaml). InputError naming the key for
// malformed YAML, an unknown family, a family left out, a material the library does not
// know (aliases are resolved to the library's names), or a material whose own texture
// family is another one (brick: plaster_smooth would undo what the classifier found); in
// the fallback: section, a min_confidence or min_share outside [0, 1], an unknown
// placement, an unknown or repeated by_look family, min_share without by_look (or by_look
// without min_share), or an unknown material.
MaterialFamilyTable parseMaterialFamilyTable(const std::string& yaml_text, const MaterialLibrary& library,
                                             const std::string& source = "material family table");
MaterialFamilyTable loadMaterialFamilyTable(const std::string& path, const MaterialLibrary& library);
// config/material_families.yaml of the package, or $ROOM_REVERB_MATERIAL_FAMILIES.
std::string defaultMaterialFamilyTablePath();

// The family called `name` (toString's spelling); InputError naming `where` otherwise.
TextureFamily textureFamilyNamed(const std::string& name, const std::string& where);

// The spelling of the placement in the table (floor, ceiling, wall, object).
std::string toString(SurfacePlacement placement);

}  // namespace room_reverb::core
