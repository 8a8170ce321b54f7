#pragma once
// Which library material a surface gets once its texture family is known
// (config/material_families.yaml). The classifier tells families apart, not materials:
// two plasters look alike. Each family names a representative material of the library,
// optionally another one by where the surface is (wooden floors are parquet, tiled
// ceilings are acoustic tiles, fabric on furniture is upholstery).
#include <map>
#include <string>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/vision/texture_family.h"

namespace room_reverb::core {

enum class SurfacePlacement { kFloor, kCeiling, kWall, kObject };

struct FamilyMaterials {
  std::string material;                               // the representative
  std::map<SurfacePlacement, std::string> placement;  // overrides by placement
};

struct MaterialFamilyTable {
  std::map<TextureFamily, FamilyMaterials> families;  // every family
  // What a surface the camera did not see well enough is taken to be: the commonest
  // indoor finish unless the file says otherwise.
  TextureFamily unseen_family = TextureFamily::kPlaster;

  // The material for a family at a placement (the override, else the representative).
  const std::string& materialFor(TextureFamily family, SurfacePlacement placement) const;
};

// Parses the table (format: config/material_families.yaml). InputError naming the key for
// malformed YAML, an unknown family, a family left out, a material the library does not
// know (aliases are resolved to the library's names), or a material whose own texture
// family is another one (brick: plaster_smooth would undo what the classifier found).
MaterialFamilyTable parseMaterialFamilyTable(const std::string& yaml_text, const MaterialLibrary& library,
                                             const std::string& source = "material family table");
MaterialFamilyTable loadMaterialFamilyTable(const std::string& path, const MaterialLibrary& library);
// config/material_families.yaml of the package, or $ROOM_REVERB_MATERIAL_FAMILIES.
std::string defaultMaterialFamilyTablePath();

// The family called `name` (toString's spelling); InputError naming `where` otherwise.
TextureFamily textureFamilyNamed(const std::string& name, const std::string& where);

}  // namespace room_reverb::core
