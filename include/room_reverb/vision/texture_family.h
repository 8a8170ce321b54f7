#pragma once
// The look of each acoustic material in the synthetic captures: every material name maps
// to a texture family (plaster, brick, wood...). The families have distinct colours and
// patterns so that a colour/texture classifier trained on the captures can tell them apart,
// and the family of a pixel's material is the classifier's truth.
#include <string>
#include <vector>

namespace room_reverb::core {

enum class TextureFamily {
  kPlaster,   // off-white, low-contrast mottling
  kBrick,     // red-brown brick courses with light mortar
  kWood,      // brown planks with grain along their length
  kCarpet,    // blue-grey, fine speckle
  kTiles,     // near-white square tiles with dark grout
  kGlass,     // dark teal panes in light frames
  kFabric,    // saturated red, weave and (curtains) folds
  kConcrete,  // mid grey, pores and formwork joints
  kMetal,     // light blue-grey, brushed
  kFoam,      // charcoal wedges (acoustic foam, mineral wool)
  kNatural,   // green-brown mottling (grass, gravel, rock)
  kOpening,   // near-black (an open window or doorway)
};

// How a family was chosen for a name: listed in the table for the project's library, by a
// keyword in the name (a material defined inline in a scene), or the default (plaster).
enum class TextureFamilySource { kTable, kKeyword, kDefault };

struct TextureFamilyChoice {
  TextureFamily family;
  TextureFamilySource source;
};

// The family of a material name (a canonical library name; resolve aliases first).
TextureFamilyChoice textureFamilyFor(const std::string& material_name);
std::string toString(TextureFamily family);
std::vector<TextureFamily> allTextureFamilies();

}  // namespace room_reverb::core
