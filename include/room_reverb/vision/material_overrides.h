#pragma once
// A user's corrections to the materials the visual route found: a YAML file naming the
// library material of some box faces and objects.
//
//   surfaces: {floor: linoleum_on_concrete, wall_y_max: brick_bare}   # kRoomSurfaceNames
//   objects:
//     - {index: 3, material: wood_panel}                  # objects[3] of the room model
//     - {label: sofa, material: fabric_upholstered_seat}  # every object with that label
//
// Both keys are optional. Names are materials or aliases of the library (written back
// under the library's own name). Label entries are applied first, then index entries, so
// that an index can make an exception to a label ("chairs are upholstered, but object 4
// is a wooden one"). The file is checked in two steps: on reading (its form, the face
// names, the materials) and against a room model (the indices, the labels, a ceiling the
// room has), each error one line naming the file and the key.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core {

struct ObjectMaterialOverride {
  std::string key;  // objects[i] in the file, for errors
  bool by_index = false;
  std::size_t index = 0;  // by_index: objects[index] of the room model
  std::string label;      // otherwise: every object with this label
  std::string material;   // the library's name
};

struct MaterialOverrideFile {
  std::string source;                           // the file, for errors
  std::map<std::string, std::string> surfaces;  // face (kRoomSurfaceNames) -> the library's name
  std::vector<ObjectMaterialOverride> objects;  // in the file's order
};

// Reads the format above. InputError naming `source` and the key for malformed YAML, a
// root that is not a map, an unknown key, an unknown face name, a material the library
// does not know (with close matches), an object entry without material or with neither or
// both of index and label, a negative or non-integer index.
MaterialOverrideFile parseMaterialOverrides(const std::string& yaml_text, const MaterialLibrary& library,
                                            const std::string& source = "materials override");
// The file at `path`; InputError naming the path when it is missing or unreadable.
MaterialOverrideFile loadMaterialOverrides(const std::string& path, const MaterialLibrary& library);

// The material the file sets for each target of `model`: the six faces in
// kRoomSurfaceNames order, then the objects; "" where the file says nothing. InputError
// naming the file and the key for an index past the model's objects, a label no object
// has (listing the labels there are), or the ceiling of a room without one.
std::vector<std::string> resolveMaterialOverrides(const MaterialOverrideFile& file, const RoomModel& model);

}  // namespace room_reverb::core
