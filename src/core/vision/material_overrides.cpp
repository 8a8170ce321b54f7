#include "room_reverb/vision/material_overrides.h"

#include <set>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"

namespace room_reverb::core {
namespace {

bool isFaceName(const std::string& name) {
  for (const char* face : kRoomSurfaceNames) {
    if (name == face) return true;
  }
  return false;
}

// The library's own name for the material at `node`; the library's close matches when it
// has no such material.
std::string libraryMaterial(const YamlReader& reader, const YAML::Node& node, const std::string& key,
                            const MaterialLibrary& library) {
  const std::string name = reader.text(node, key);
  try {
    return library.get(name).name;
  } catch (const InputError& e) {
    reader.fail(node, key, std::string(e.what()) + " in the library (" + MaterialLibrary::defaultPath() + ")");
  }
}

ObjectMaterialOverride parseObject(const YamlReader& reader, const YAML::Node& node, std::size_t i,
                                   const MaterialLibrary& library) {
  ObjectMaterialOverride entry;
  entry.key = "objects[" + std::to_string(i) + "]";
  reader.requireMap(node, entry.key);
  for (const auto& field : node) {
    const std::string name = reader.text(field.first, entry.key + " key");
    if (name != "index" && name != "label" && name != "material") {
      reader.fail(field.first, entry.key + "." + name, "unknown key (expected index or label, and material)");
    }
  }
  const YAML::Node index = node["index"], label = node["label"];
  const bool has_index = index.IsDefined() && !index.IsNull(), has_label = label.IsDefined() && !label.IsNull();
  if (has_index == has_label) {
    reader.fail(node, entry.key, "give either index (one object) or label (every object with it), not both or neither");
  }
  if (has_index) {
    long long value = -1;
    try {
      if (index.IsScalar()) value = index.as<long long>();
    } catch (const YAML::Exception&) {
      value = -1;
    }
    if (value < 0) reader.fail(index, entry.key + ".index", "must be an object's index, a whole number from 0 (got " + index.Scalar() + ")");
    entry.by_index = true;
    entry.index = static_cast<std::size_t>(value);
  } else {
    entry.label = reader.text(label, entry.key + ".label");
  }
  entry.material = libraryMaterial(reader, reader.require(node, "material", entry.key + ".material"),
                                   entry.key + ".material", library);
  return entry;
}

}  // namespace

MaterialOverrideFile parseMaterialOverrides(const std::string& yaml_text, const MaterialLibrary& library,
                                            const std::string& source) {
  const YamlReader reader(source);
  return reader.guarded("materials override", [&] {
    const YAML::Node root = reader.loadMap(yaml_text, "a materials override with surfaces and/or objects");
    MaterialOverrideFile file;
    file.source = source;
    for (const auto& item : root) {
      const std::string name = reader.text(item.first, "key");
      // A misspelt key would otherwise leave the user's corrections silently unapplied.
      if (name != "surfaces" && name != "objects") reader.fail(item.first, name, "unknown key (expected surfaces or objects)");
    }
    const YAML::Node surfaces = root["surfaces"];
    if (surfaces.IsDefined() && !surfaces.IsNull()) {
      reader.requireMap(surfaces, "surfaces");
      for (const auto& entry : surfaces) {
        const std::string face = reader.text(entry.first, "surfaces key");
        const std::string key = "surfaces." + face;
        if (!isFaceName(face)) {
          reader.fail(entry.first, key, "unknown surface (use floor, ceiling, wall_x_min, wall_x_max, wall_y_min, wall_y_max)");
        }
        file.surfaces[face] = libraryMaterial(reader, entry.second, key, library);
      }
    }
    const YAML::Node objects = root["objects"];
    if (objects.IsDefined() && !objects.IsNull()) {
      if (!objects.IsSequence()) reader.fail(objects, "objects", "must be a list of {index or label, material}");
      for (std::size_t i = 0; i < objects.size(); ++i) file.objects.push_back(parseObject(reader, objects[i], i, library));
    }
    return file;
  });
}

MaterialOverrideFile loadMaterialOverrides(const std::string& path, const MaterialLibrary& library) {
  return parseMaterialOverrides(readTextFile(path, "materials override"), library, path);
}

std::vector<std::string> resolveMaterialOverrides(const MaterialOverrideFile& file, const RoomModel& model) {
  const auto fail = [&](const std::string& key, const std::string& message) {
    throw InputError(file.source + ": " + key + ": " + message);
  };
  std::vector<std::string> chosen(kRoomSurfaceNames.size() + model.objects.size());
  for (std::size_t f = 0; f < kRoomSurfaceNames.size(); ++f) {
    const auto it = file.surfaces.find(kRoomSurfaceNames[f]);
    if (it == file.surfaces.end()) continue;
    if (f == 1 && !model.has_ceiling) fail("surfaces.ceiling", "the room has no ceiling (its top is open)");
    chosen[f] = it->second;
  }
  const std::size_t base = kRoomSurfaceNames.size();
  for (const bool by_index : {false, true}) {
    for (const ObjectMaterialOverride& entry : file.objects) {
      if (entry.by_index != by_index) continue;
      if (by_index) {
        if (entry.index >= model.objects.size()) {
          fail(entry.key + ".index", std::to_string(entry.index) + " is past the room's objects (" +
                                         (model.objects.empty() ? std::string("it has none")
                                                                : "0 to " + std::to_string(model.objects.size() - 1)) +
                                         ")");
        }
        chosen[base + entry.index] = entry.material;
        continue;
      }
      bool matched = false;
      std::set<std::string> labels;
      for (std::size_t k = 0; k < model.objects.size(); ++k) {
        labels.insert(model.objects[k].label);
        if (model.objects[k].label != entry.label) continue;
        chosen[base + k] = entry.material;
        matched = true;
      }
      if (!matched) {
        std::string known;
        for (const std::string& label : labels) known += (known.empty() ? "labels: " : ", ") + label;
        fail(entry.key + ".label", "no object is labelled '" + entry.label + "' (" +
                                       (known.empty() ? std::string("the room has no objects") : known) + ")");
      }
    }
  }
  return chosen;
}

}  // namespace room_reverb::core
