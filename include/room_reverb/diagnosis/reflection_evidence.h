#pragma once
// Early reflections as evidence for the diagnosis (the catalogue's missing_reflector
// signature: "a strong measured early reflection with no simulated counterpart"): one
// error per B-format pair that counts the strong measured reflections the model's
// specular paths do not explain.
//
// The model side is its image-source paths, not the RSAO of its simulated response: in
// the synthesised response the scattered energy of the first 30 ms arrives as a sparse
// Poisson train of impulses (impulse_response_synthesis.h), and the RSAO reads those as
// reflections 5-10 dB below the direct sound that change with every ray-tracing seed. Set
// against such a list, the measured reflections of a model that matches its measurement
// exactly leave 40-110 JND unmatched per pair (planted test rooms). The paths
// are the same for every seed, so the term adds nothing to the diagnosis's noise.
#include <optional>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/diagnosis/unexplained_reflections.h"

namespace room_reverb::core {

// The error of one pair in JND (1 dB of level per JND, as the early-energy windows): over
// the strong measured reflections that no path explains and that a missing surface inside
// the room could make (unexplained_reflections.h), the sum of their levels above -14 dB
// (each capped at 10, as every term of the diagnosis; the sum is not).
// A reflection just strong enough to count adds almost nothing, so the term does not jump
// when a level crosses the threshold.
//
// Only this direction is counted. Strong paths the measurement does not show are not a
// second part of the term: the RSAO misses or merges some real paths
// (a floor and a ceiling reflection 0.3 ms apart), and a model could lower that part by
// weakening its paths (more scattering) instead of by placing them right.
double reflectionMismatchJnd(const std::vector<RelativeReflection>& measured, const std::vector<SpecularPath>& paths,
                             const MeasurementPair& pair, const AcousticScene& scene, double speed_of_sound_m_s);

}  // namespace room_reverb::core
