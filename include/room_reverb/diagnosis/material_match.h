#pragma once
// The library material that absorbs most like a fitted absorption: what a per-surface fit
// says the surface is made of, and whether anything real absorbs like that at all.
#include <string>

#include "room_reverb/acoustics/material.h"

namespace room_reverb::core {

struct MaterialMatch {
  std::string material;             // "" for an empty library
  double max_difference = 0.0;      // largest absolute difference in absorption, 125 Hz - 8 kHz
  double worst_band_hz = 0.0;       // where it is
};

// A fit further than this from every library material in some band absorbs like nothing
// the library knows: a fit taking up another cause's error (e.g. concrete at 0.38 in a
// BRAS CR2 model without air absorption) rather than a surface's true material.
// 0.15 is a choice, not a measurement: three times the 0.05 within which the planted
// tests hold a fitted absorption to the truth.
constexpr double kImplausibleAbsorptionDifference = 0.15;

// The library material minimising the largest absolute difference over the octave bands
// 125 Hz - 8 kHz (the bands the diagnosis scores; 63 Hz and 16 kHz are extrapolated by the
// fits).
MaterialMatch nearestMaterial(const OctaveBandValues& absorption, const MaterialLibrary& library);

}  // namespace room_reverb::core
