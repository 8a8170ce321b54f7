#include "room_reverb/vision/material_families.h"

#include <set>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"

namespace room_reverb::core {
namespace {

const std::map<std::string, SurfacePlacement>& placementKeys() {
  static const std::map<std::string, SurfacePlacement> keys = {{"floor", SurfacePlacement::kFloor},
                                                               {"ceiling", SurfacePlacement::kCeiling},
                                                               {"wall", SurfacePlacement::kWall},
                                                               {"object", SurfacePlacement::kObject}};
  return keys;
}

// The library's name for `name`, checked to be drawn as `family`.
std::string familyMaterial(const YamlReader& reader, const YAML::Node& node, const std::string& key,
                           TextureFamily family, const MaterialLibrary& library) {
  const std::string name = reader.text(node, key);
  if (!library.contains(name)) reader.fail(node, key, "'" + name + "' is not a material of the library (" + MaterialLibrary::defaultPath() + ")");
  const std::string canonical = library.get(name).name;
  const TextureFamily own = textureFamilyFor(canonical).family;
  if (own != family) {
    reader.fail(node, key, "'" + name + "' looks like " + toString(own) + ", not " + toString(family) +
                               "; name a material of the " + toString(family) + " family");
  }
  return canonical;
}

}  // namespace

TextureFamily textureFamilyNamed(const std::string& name, const std::string& where) {
  for (const TextureFamily family : allTextureFamilies()) {
    if (toString(family) == name) return family;
  }
  std::string known;
  for (const TextureFamily family : allTextureFamilies()) known += (known.empty() ? "" : ", ") + toString(family);
  throw InputError(where + ": unknown texture family '" + name + "' (one of " + known + ")");
}

const std::string& MaterialFamilyTable::materialFor(TextureFamily family, SurfacePlacement placement) const {
  const auto it = families.find(family);
  if (it == families.end()) throw InputError("material family table: no entry for " + toString(family));
  const auto special = it->second.placement.find(placement);
  return special != it->second.placement.end() ? special->second : it->second.material;
}

MaterialFamilyTable parseMaterialFamilyTable(const std::string& yaml_text, const MaterialLibrary& library,
                                             const std::string& source) {
  const YamlReader reader(source);
  return reader.guarded("material family table", [&] {
    const YAML::Node root = reader.loadMap(yaml_text, "material family table");
    MaterialFamilyTable table;
    if (root["unseen_family"]) {
      table.unseen_family = textureFamilyNamed(reader.text(root["unseen_family"], "unseen_family"), source + ": unseen_family");
    }
    const YAML::Node families = reader.require(root, "families", "families");
    reader.requireMap(families, "families");
    for (const auto& item : families) {
      const std::string name = reader.text(item.first, "families key");
      const std::string key = "families." + name;
      const TextureFamily family = textureFamilyNamed(name, source + ": " + key);
      if (table.families.count(family)) reader.fail(item.first, key, "listed twice");
      reader.requireMap(item.second, key);
      FamilyMaterials entry;
      entry.material = familyMaterial(reader, reader.require(item.second, "material", key + ".material"), key + ".material",
                                      family, library);
      for (const auto& field : item.second) {
        const std::string field_name = reader.text(field.first, key + " key");
        if (field_name == "material") continue;
        const auto placement = placementKeys().find(field_name);
        if (placement == placementKeys().end()) {
          reader.fail(field.first, key + "." + field_name, "unknown key (expected material, floor, ceiling, wall or object)");
        }
        entry.placement[placement->second] = familyMaterial(reader, field.second, key + "." + field_name, family, library);
      }
      table.families[family] = entry;
    }
    for (const TextureFamily family : allTextureFamilies()) {
      if (!table.families.count(family)) reader.fail(families, "families." + toString(family), "missing (every family needs a material)");
    }
    return table;
  });
}

MaterialFamilyTable loadMaterialFamilyTable(const std::string& path, const MaterialLibrary& library) {
  return parseMaterialFamilyTable(readTextFile(path, "material family table"), library, path);
}

std::string defaultMaterialFamilyTablePath() {
  return packageFilePath("ROOM_REVERB_MATERIAL_FAMILIES", "config/material_families.yaml");
}

}  // namespace room_reverb::core
