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

// [0, 1], the share of a vote.
double share(const YamlReader& reader, const YAML::Node& node, const std::string& key) {
  const double value = reader.number(node, key);
  if (value < 0.0 || value > 1.0) reader.fail(node, key, "must be a share of the vote in [0, 1] (got " + node.Scalar() + ")");
  return value;
}

PlacementFallback parsePlacementFallback(const YamlReader& reader, const YAML::Node& node, const std::string& key,
                                         const MaterialLibrary& library) {
  reader.requireMap(node, key);
  PlacementFallback rule;
  const YAML::Node material = reader.require(node, "material", key + ".material",
                                             "missing (the placement's commonest material)");
  rule.material = reader.text(material, key + ".material");
  if (!library.contains(rule.material)) {
    reader.fail(material, key + ".material", "'" + rule.material + "' is not a material of the library (" + MaterialLibrary::defaultPath() + ")");
  }
  rule.material = library.get(rule.material).name;
  for (const auto& field : node) {
    const std::string name = reader.text(field.first, key + " key");
    if (name != "material" && name != "by_look" && name != "min_share") {
      reader.fail(field.first, key + "." + name, "unknown key (expected material, by_look or min_share)");
    }
  }
  const YAML::Node by_look = node["by_look"];
  if (by_look.IsDefined() && !by_look.IsNull()) {
    if (!by_look.IsSequence() || by_look.size() == 0) reader.fail(by_look, key + ".by_look", "must be a list of texture families");
    for (std::size_t i = 0; i < by_look.size(); ++i) {
      const std::string item_key = key + ".by_look[" + std::to_string(i) + "]";
      const TextureFamily family = textureFamilyNamed(reader.text(by_look[i], item_key), reader.source() + ": " + item_key);
      for (const TextureFamily listed : rule.by_look) {
        if (listed == family) reader.fail(by_look[i], item_key, "'" + toString(family) + "' is listed twice");
      }
      rule.by_look.push_back(family);
    }
  }
  const YAML::Node min_share = node["min_share"];
  const bool has_share = min_share.IsDefined() && !min_share.IsNull();
  if (has_share != !rule.by_look.empty()) {
    reader.fail(has_share ? min_share : node, key + (has_share ? ".min_share" : ".by_look"),
                "by_look and min_share go together: the families to look at and the share of the vote one needs");
  }
  if (has_share) rule.min_share = share(reader, min_share, key + ".min_share");
  return rule;
}

MaterialFallback parseFallback(const YamlReader& reader, const YAML::Node& node, const MaterialLibrary& library) {
  reader.requireMap(node, "fallback");
  MaterialFallback fallback;
  fallback.min_confidence =
      share(reader, reader.require(node, "min_confidence", "fallback.min_confidence",
                                   "missing (the winning share of the vote below which a face falls back)"),
            "fallback.min_confidence");
  for (const auto& field : node) {
    const std::string name = reader.text(field.first, "fallback key");
    if (name == "min_confidence") continue;
    const auto placement = placementKeys().find(name);
    if (placement == placementKeys().end()) {
      reader.fail(field.first, "fallback." + name, "unknown key (expected min_confidence, floor, ceiling, wall or object)");
    }
    fallback.rules[placement->second] = parsePlacementFallback(reader, field.second, "fallback." + name, library);
  }
  return fallback;
}

}  // namespace

std::string toString(SurfacePlacement placement) {
  for (const auto& [name, value] : placementKeys()) {
    if (value == placement) return name;
  }
  return "object";
}

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
    const YAML::Node fallback = root["fallback"];
    if (fallback.IsDefined() && !fallback.IsNull()) table.fallback = parseFallback(reader, fallback, library);
    for (const auto& item : root) {
      const std::string name = reader.text(item.first, "key");
      if (name != "unseen_family" && name != "families" && name != "fallback") {
        reader.fail(item.first, name, "unknown key (expected unseen_family, families or fallback)");
      }
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
