#include "texture_patterns.h"

#include <algorithm>
#include <cmath>

#include "value_noise.h"

namespace room_reverb::core::capture_detail {
namespace {

constexpr double kTwoPi = 6.283185307179586;

// Distinct base colours per family (RGB), chosen so that hue and brightness alone already
// separate most families: plaster off-white, brick red-brown, wood mid brown, carpet
// blue-grey, tiles near-white with dark grout, glass dark teal, fabric burgundy, concrete
// mid grey, metal light blue-grey, foam charcoal, natural green or grey-brown, opening black.
const Rgb kPlaster(222, 218, 208);
const Rgb kBrick(152, 74, 52), kMortar(188, 182, 170);
const Rgb kWood(150, 100, 58);
const Rgb kCarpet(72, 82, 114);
const Rgb kTile(230, 232, 228), kGrout(105, 105, 100);
const Rgb kGlass(62, 100, 112), kFrame(236, 236, 232);
const Rgb kFabric(138, 38, 54);
const Rgb kConcrete(138, 136, 130);
const Rgb kMetal(172, 180, 190);
const Rgb kFoam(50, 50, 56);
const Rgb kGrass(72, 118, 46), kStone(128, 118, 104);
const Rgb kOpening(18, 18, 22);
const Rgb kPaint(226, 222, 212);

std::uint64_t sub(const SurfaceSample& p, std::uint64_t what) { return hashCombine(p.salt, what); }

// Distance (metres) from a position within a cell of size `period` to the nearer border.
double borderDistance(double fraction, double period) { return std::min(fraction, 1.0 - fraction) * period; }

// A running bond of courses: returns the mortar coverage and the brick's own random tone.
struct Bond {
  double mortar;
  double tone;  // in [0, 1), one value per brick
  double hue;   // in [0, 1), one value per brick
};
Bond runningBond(const SurfaceSample& p, double length_m, double course_m, double joint_half_m) {
  const Cell row = cellOf(p.t_m, course_m);
  // Alternate courses shifted by half a unit, plus a little irregularity per course.
  const double shift = (row.index & 1 ? 0.5 * length_m : 0.0) + 0.04 * length_m * latticeUnit(sub(p, 11), row.index, 0);
  const Cell column = cellOf(p.s_m + shift, length_m);
  const double mortar = std::max(lineCoverage(borderDistance(row.fraction, course_m), joint_half_m, p.footprint_m),
                                 lineCoverage(borderDistance(column.fraction, length_m), joint_half_m, p.footprint_m));
  return {mortar, latticeUnit(sub(p, 12), column.index, row.index), latticeUnit(sub(p, 4), column.index, row.index)};
}

Rgb mix(const Rgb& a, const Rgb& b, double t) { return a + (b - a) * t; }

}  // namespace

Rgb plasterPattern(const MaterialLook& look, const SurfaceSample& p) {
  const double amount = look.rough ? 2.0 : 1.0;
  const double mottle = fractalNoise(sub(p, 1), p.s_m, p.t_m, 0.6, 7, 0.62, p.footprint_m);
  const double grain = fractalNoise(sub(p, 2), p.s_m, p.t_m, 0.03, 3, 0.6, p.footprint_m);
  return kPlaster * look.tint * (1.0 + amount * (0.08 * mottle + 0.04 * grain));
}

Rgb brickPattern(const MaterialLook& look, const SurfaceSample& p) {
  const Bond bond = runningBond(p, 0.225, 0.075, 0.005);
  const double surface = fractalNoise(sub(p, 3), p.s_m, p.t_m, 0.1, 4, 0.6, p.footprint_m);
  Rgb brick = kBrick * look.tint * (0.78 + 0.4 * bond.tone + 0.12 * surface);
  brick[0] *= 0.92 + 0.16 * bond.hue;  // some bricks redder than others
  Rgb mortar = kMortar * (1.0 + 0.06 * surface);
  if (look.painted) {
    brick = mix(brick, kPaint * look.tint, 0.8);
    mortar = mix(mortar, kPaint * look.tint * 0.9, 0.8);
  }
  return mix(brick, mortar, bond.mortar);
}

Rgb woodPattern(const MaterialLook& look, const SurfaceSample& p) {
  constexpr double kPlankWidth = 0.14;
  const Cell row = cellOf(p.t_m, kPlankWidth);
  const double plank_length = 1.2 + 1.2 * latticeUnit(sub(p, 5), row.index, 0);
  const Cell along = cellOf(p.s_m + plank_length * latticeUnit(sub(p, 6), row.index, 1), plank_length);
  const double tone = latticeUnit(sub(p, 7), row.index, along.index);
  // Grain: noise stretched along the plank, warped so the streaks wander.
  const std::uint64_t plank_salt = hashCombine(sub(p, 8), static_cast<std::uint64_t>(row.index * 7919 + along.index));
  const double warp = 0.02 * fractalNoise(plank_salt, p.s_m, p.t_m, 0.5, 2, 0.5, p.footprint_m);
  const double grain = stretchedNoise(hashCombine(plank_salt, 1), p.s_m, p.t_m + warp, 0.6, 0.025, 4, 0.65, p.footprint_m);
  const double seam = std::max(lineCoverage(borderDistance(row.fraction, kPlankWidth), 0.0015, p.footprint_m),
                               lineCoverage(borderDistance(along.fraction, plank_length), 0.0015, p.footprint_m));
  const Rgb wood = kWood * look.tint * (0.8 + 0.35 * tone + 0.22 * grain);
  return mix(wood, wood * 0.45, seam);
}

Rgb carpetPattern(const MaterialLook& look, const SurfaceSample& p) {
  const double speckle = fractalNoise(sub(p, 9), p.s_m, p.t_m, 0.012, 2, 0.5, p.footprint_m);
  const double mottle = fractalNoise(sub(p, 10), p.s_m, p.t_m, 0.4, 4, 0.5, p.footprint_m);
  return kCarpet * look.tint * (1.0 + 0.3 * speckle + 0.1 * mottle);
}

Rgb tilesPattern(const MaterialLook& look, const SurfaceSample& p) {
  const double size = look.large_tiles ? 0.6 : 0.3;
  const Cell u = cellOf(p.s_m, size), v = cellOf(p.t_m, size);
  const double grout = std::max(lineCoverage(borderDistance(u.fraction, size), 0.003, p.footprint_m),
                                lineCoverage(borderDistance(v.fraction, size), 0.003, p.footprint_m));
  const double tone = latticeUnit(sub(p, 13), u.index, v.index);
  // Ceiling tiles are fissured (fine dark flecks); ceramic tiles have a faint cloudiness.
  const double detail = look.large_tiles ? fractalNoise(sub(p, 14), p.s_m, p.t_m, 0.015, 2, 0.5, p.footprint_m)
                                         : fractalNoise(sub(p, 14), p.s_m, p.t_m, 0.15, 4, 0.6, p.footprint_m);
  const Rgb tile = kTile * look.tint * (0.93 + 0.08 * tone + 0.07 * detail);
  return mix(tile, kGrout * look.tint, grout);
}

Rgb glassPattern(const MaterialLook& look, const SurfaceSample& p) {
  constexpr double kPaneWidth = 1.0, kPaneHeight = 1.2;
  const Cell u = cellOf(p.s_m, kPaneWidth), v = cellOf(p.t_m, kPaneHeight);
  const double frame = std::max(lineCoverage(borderDistance(u.fraction, kPaneWidth), 0.03, p.footprint_m),
                                lineCoverage(borderDistance(v.fraction, kPaneHeight), 0.03, p.footprint_m));
  // What lies behind or is mirrored in the pane, frozen onto it: soft, diagonal streaks.
  const double cloud = fractalNoise(sub(p, 15), p.s_m, p.t_m, 1.2, 5, 0.6, p.footprint_m);
  const double streak = stretchedNoise(sub(p, 16), p.s_m + p.t_m, p.s_m - p.t_m, 0.08, 1.0, 3, 0.5, p.footprint_m);
  const Rgb pane = kGlass * look.tint * (1.0 + 0.3 * cloud + 0.15 * streak);
  return mix(pane, kFrame, frame);
}

Rgb fabricPattern(const MaterialLook& look, const SurfaceSample& p) {
  const double weave = fractalNoise(sub(p, 17), p.s_m, p.t_m, 0.008, 2, 0.5, p.footprint_m);
  const double mottle = fractalNoise(sub(p, 18), p.s_m, p.t_m, 0.15, 4, 0.55, p.footprint_m);
  double shade = 1.0 + 0.12 * weave + 0.12 * mottle;
  if (look.folds) {
    // Vertical folds about 12 cm apart whose spacing wanders along the curtain.
    const double phase = kTwoPi * p.s_m / 0.12 + 2.5 * fractalNoise(sub(p, 19), p.s_m, 0.0, 0.6, 2, 0.5, 0.0);
    shade *= 0.8 + 0.2 * std::sin(phase);
  }
  return kFabric * look.tint * shade;
}

Rgb concretePattern(const MaterialLook& look, const SurfaceSample& p) {
  const double mottle = fractalNoise(sub(p, 20), p.s_m, p.t_m, 0.8, 7, 0.58, p.footprint_m);
  // Pores: sparse dark spots a few millimetres wide, faded out when a sample is larger.
  const double pore_noise = valueNoise(sub(p, 21), p.s_m / 0.008, p.t_m / 0.008);
  const double pores = std::clamp((pore_noise - 0.82) / 0.1, 0.0, 1.0) * std::clamp(0.008 / std::max(p.footprint_m, 1e-9) - 1.0, 0.0, 1.0);
  double joint = 0.0;
  if (look.blocks) {
    joint = runningBond(p, 0.4, 0.2, 0.005).mortar;
  } else {
    const Cell u = cellOf(p.s_m, 1.2), v = cellOf(p.t_m, 0.6);  // formwork panels
    joint = std::max(lineCoverage(borderDistance(u.fraction, 1.2), 0.002, p.footprint_m),
                     lineCoverage(borderDistance(v.fraction, 0.6), 0.002, p.footprint_m));
  }
  Rgb concrete = kConcrete * look.tint * (1.0 + 0.14 * mottle - 0.3 * pores);
  if (look.painted) concrete = mix(concrete, kPaint * look.tint * 0.92, 0.6);
  return mix(concrete, concrete * 0.65, joint);
}

Rgb metalPattern(const MaterialLook& look, const SurfaceSample& p) {
  const double brushed = stretchedNoise(sub(p, 22), p.s_m, p.t_m, 0.4, 0.01, 3, 0.6, p.footprint_m);
  const double sheen = fractalNoise(sub(p, 23), p.s_m, p.t_m, 1.0, 3, 0.5, p.footprint_m);
  const double seam = lineCoverage(borderDistance(cellOf(p.s_m, 1.0).fraction, 1.0), 0.002, p.footprint_m);
  const Rgb metal = kMetal * look.tint * (1.0 + 0.1 * brushed + 0.12 * sheen);
  return mix(metal, metal * 0.55, seam);
}

Rgb foamPattern(const MaterialLook& look, const SurfaceSample& p) {
  // Wedges 10 cm across: light and dark faces as the slopes turn towards or away from the
  // room; the sine keeps it band-limited.
  const double period = 0.1;
  const double visible = std::clamp(period / std::max(p.footprint_m, 1e-9) / 4.0 - 1.0, 0.0, 1.0);
  const double wedges = std::sin(kTwoPi * p.s_m / period) * std::sin(kTwoPi * p.t_m / period);
  const double fibre = fractalNoise(sub(p, 24), p.s_m, p.t_m, 0.02, 2, 0.5, p.footprint_m);
  return kFoam * look.tint * (1.0 + 0.35 * visible * wedges + 0.1 * fibre);
}

Rgb naturalPattern(const MaterialLook& look, const SurfaceSample& p) {
  const double patches = fractalNoise(sub(p, 25), p.s_m, p.t_m, 0.5, 5, 0.6, p.footprint_m);
  const double detail = fractalNoise(sub(p, 26), p.s_m, p.t_m, 0.02, 3, 0.6, p.footprint_m);
  const Rgb base = look.greenery ? kGrass : kStone;
  return base * look.tint * (1.0 + 0.25 * patches + 0.25 * detail);
}

Rgb openingPattern(const MaterialLook& look, const SurfaceSample& p) {
  return kOpening * look.tint * (1.0 + 0.1 * fractalNoise(sub(p, 27), p.s_m, p.t_m, 0.5, 3, 0.5, p.footprint_m));
}

Rgb familyMeanColor(const MaterialLook& look) {
  switch (look.family) {
    case TextureFamily::kPlaster: return kPlaster * look.tint;
    case TextureFamily::kBrick: return look.painted ? kPaint * look.tint : kBrick * look.tint;
    case TextureFamily::kWood: return kWood * look.tint * 0.97;
    case TextureFamily::kCarpet: return kCarpet * look.tint;
    case TextureFamily::kTiles: return kTile * look.tint * 0.97;
    case TextureFamily::kGlass: return kGlass * look.tint;
    case TextureFamily::kFabric: return kFabric * look.tint * (look.folds ? 0.8 : 1.0);
    case TextureFamily::kConcrete: return look.painted ? mix(kConcrete, kPaint * 0.92, 0.6) * look.tint : kConcrete * look.tint;
    case TextureFamily::kMetal: return kMetal * look.tint;
    case TextureFamily::kFoam: return kFoam * look.tint;
    case TextureFamily::kNatural: return (look.greenery ? kGrass : kStone) * look.tint;
    case TextureFamily::kOpening: return kOpening * look.tint;
  }
  return kPlaster;
}

}  // namespace room_reverb::core::capture_detail
