#pragma once
// Strong early reflections of a measurement that no specular path of the model explains:
// the trace of a surface the model lacks, from which the diagnosis places missing
// reflectors and scores how well a model accounts for the measured reflections
// (reflection_evidence.h).
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/evaluation/measured_reflections.h"
#include "room_reverb/evaluation/reflection_matching.h"

namespace room_reverb::core {

// Whether a specular path (not the direct sound) arrives within 0.6 ms of the reflection,
// counted from its own direct sound, and within 30 degrees of its direction.
bool pathMatchesReflection(const SpecularPath& path, double direct_delay_s, const RelativeReflection& reflection);
// Whether any of `paths` (paths.front() the direct sound) does.
bool explainedBySpecularPath(const std::vector<SpecularPath>& paths, const RelativeReflection& reflection);
// The stricter rule of the reflection term (reflection_evidence.h): only paths at most 24
// dB below the direct sound count, alone or, for paths each within 0.6 ms of the
// reflection (inside the RSAO's 2 ms analysis window), merged into their energy-weighted
// mean direction (the one reflection the RSAO reads from a floor and a ceiling path 0.3 ms
// apart comes from the horizon).
bool explainedByAudiblePaths(const std::vector<SpecularPath>& paths, const RelativeReflection& reflection);

enum class ExplanationRule { kAnyPath, kAudibleOrMerged };

// A path's level re the direct sound in dB: its energy over the octaves 500 Hz - 4 kHz,
// which carry most of a reflection's energy in the RSAO's window.
double pathLevelDb(const SpecularPath& path, const SpecularPath& direct);

// A strong reflection no specular path explains, placed by image-source geometry: the
// point P on the arrival ray from the receiver R whose path from the source S is the
// reflection's length L (|S - P| + |P - R| = L):
//   P = R + d u,  d = (L^2 - |S - R|^2) / (2 (L - u . (S - R))),
// reflecting with the normal that bisects the directions from P to S and to R.
struct UnexplainedReflection {
  Eigen::Vector3d point, normal;
  double level_db = 0.0;  // re the direct sound
};

// The strong ones of `reflections` (a measurement's, relative to its direct sound) that no
// path explains and whose point lies inside the room, 0.3 m or more from its surfaces. A
// point outside the room or on a surface is one the model has (its reflection mistimed,
// or of a higher order than its image sources, or two coincident ones the RSAO merged
// into one direction), not a missing surface.
std::vector<UnexplainedReflection> unexplainedReflections(const std::vector<RelativeReflection>& reflections,
                                                          const std::vector<SpecularPath>& paths,
                                                          const MeasurementPair& pair, const AcousticScene& scene,
                                                          double speed_of_sound_m_s,
                                                          ExplanationRule rule = ExplanationRule::kAnyPath);

}  // namespace room_reverb::core
