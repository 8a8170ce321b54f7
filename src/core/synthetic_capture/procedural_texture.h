#pragma once
// Procedural surface textures of the synthetic captures: colour as a function of a point's
// 2D coordinates on its surface (metres), the surface, the material and the seed. Being a
// function of the surface point alone (not of the view), a texture is identical in the two
// cameras of the stereo rig, as the matcher needs.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>

#include "room_reverb/synthetic_capture/photo_textures.h"
#include "room_reverb/vision/texture_family.h"

namespace room_reverb::core::capture_detail {

using Rgb = Eigen::Array3d;  // red, green, blue in grey levels 0..255 (before shading)

// What a material looks like: its family, a tint that tells materials of one family apart,
// variant switches read from the name, and the texture contrast (1 normal, near 0 for a
// "poorly textured" material: its texture fades towards its mean colour).
struct MaterialLook {
  TextureFamily family = TextureFamily::kPlaster;
  Rgb tint = Rgb::Ones();
  double contrast = 1.0;
  bool painted = false;   // painted brick or block: pale, low-contrast courses
  bool rough = false;     // rough plaster: stronger mottling
  bool folds = false;     // curtains and blinds: vertical folds
  bool blocks = false;    // concrete block: large courses
  bool large_tiles = false;  // suspended ceiling tiles: 0.6 m grid
  bool greenery = false;  // grass rather than gravel or rock
  // A photograph of the family instead of the drawn pattern (photo_textures.h), tiled at
  // photo_width_m per image width.
  std::shared_ptr<const PhotoTexture> photo;
  double photo_width_m = 1.0;
};

// `canonical_name` is the library's name (aliases resolved). The tint depends on the name
// only, not on the seed, so a material keeps its colour across captures.
MaterialLook makeMaterialLook(const std::string& canonical_name, double contrast);

// A point on a surface: s along the surface (horizontal on walls), t across it (vertical
// on walls), metres; `salt` identifies the surface and seed; `footprint_m` is the size of
// one sample on the surface (detail finer than this is filtered out).
struct SurfaceSample {
  double s_m = 0.0;
  double t_m = 0.0;
  std::uint64_t salt = 0;
  double footprint_m = 0.0;
};

Rgb textureColor(const MaterialLook& look, const SurfaceSample& sample);

}  // namespace room_reverb::core::capture_detail
