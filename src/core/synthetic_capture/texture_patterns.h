#pragma once
// One pattern per texture family (procedural_texture.h): each returns the unshaded colour
// of a surface point. Sizes are those of the real thing (a brick is 215 x 65 mm with 10 mm
// joints), so that texture scale is a depth cue as it is in a photograph.
#include "procedural_texture.h"

namespace room_reverb::core::capture_detail {

Rgb plasterPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb brickPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb woodPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb carpetPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb tilesPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb glassPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb fabricPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb concretePattern(const MaterialLook& look, const SurfaceSample& p);
Rgb metalPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb foamPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb naturalPattern(const MaterialLook& look, const SurfaceSample& p);
Rgb openingPattern(const MaterialLook& look, const SurfaceSample& p);

// The colour a family's pattern averages to (what a "poorly textured" surface fades to).
Rgb familyMeanColor(const MaterialLook& look);

}  // namespace room_reverb::core::capture_detail
