#include "procedural_texture.h"

#include <algorithm>

#include "texture_patterns.h"
#include "value_noise.h"

namespace room_reverb::core::capture_detail {
namespace {

bool has(const std::string& name, const char* word) { return name.find(word) != std::string::npos; }


}  // namespace

MaterialLook makeMaterialLook(const std::string& canonical_name, double contrast) {
  MaterialLook look;
  look.family = textureFamilyFor(canonical_name).family;
  look.contrast = contrast;
  look.painted = has(canonical_name, "painted");
  look.rough = has(canonical_name, "rough") || has(canonical_name, "coarse");
  look.folds = has(canonical_name, "curtain") || has(canonical_name, "blind");
  look.blocks = has(canonical_name, "block");
  look.large_tiles = has(canonical_name, "ceiling");
  look.greenery = has(canonical_name, "grass");
  // Up to +-6 % per channel, from the name alone: two plasters differ slightly, a plaster
  // and a brick differ a lot.
  const std::uint64_t h = nameHash(canonical_name);
  for (int c = 0; c < 3; ++c) {
    const double u = static_cast<double>((h >> (16 * c)) & 0xffff) / 65535.0;
    look.tint[c] = 1.0 + 0.12 * (u - 0.5);
  }
  return look;
}

Rgb textureColor(const MaterialLook& look, const SurfaceSample& sample) {
  if (look.photo) {
    const Rgb color = photoTextureColor(*look.photo, look.photo_width_m, sample.s_m, sample.t_m, sample.footprint_m);
    return (look.tint * (look.photo->mean_rgb + look.contrast * (color - look.photo->mean_rgb))).max(0.0).min(255.0);
  }
  Rgb color;
  switch (look.family) {
    case TextureFamily::kPlaster: color = plasterPattern(look, sample); break;
    case TextureFamily::kBrick: color = brickPattern(look, sample); break;
    case TextureFamily::kWood: color = woodPattern(look, sample); break;
    case TextureFamily::kCarpet: color = carpetPattern(look, sample); break;
    case TextureFamily::kTiles: color = tilesPattern(look, sample); break;
    case TextureFamily::kGlass: color = glassPattern(look, sample); break;
    case TextureFamily::kFabric: color = fabricPattern(look, sample); break;
    case TextureFamily::kConcrete: color = concretePattern(look, sample); break;
    case TextureFamily::kMetal: color = metalPattern(look, sample); break;
    case TextureFamily::kFoam: color = foamPattern(look, sample); break;
    case TextureFamily::kNatural: color = naturalPattern(look, sample); break;
    case TextureFamily::kOpening: color = openingPattern(look, sample); break;
  }
  if (look.contrast != 1.0) {
    const Rgb mean = familyMeanColor(look);
    color = mean + look.contrast * (color - mean);
  }
  return color.max(0.0).min(255.0);
}

}  // namespace room_reverb::core::capture_detail
