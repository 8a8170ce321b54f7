#pragma once
// Strong early reflections of a measurement that no specular path of the model explains:
// the trace of a surface the model lacks, from which the diagnosis places missing
// reflectors.
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/evaluation/reflection_matching.h"

namespace room_reverb::core {

// A reflection is strong when it comes within 30 ms of the direct sound (later ones crowd
// too densely to tell apart) and at most 14 dB below it.
constexpr double kStrongReflectionLatestS = 0.030;
constexpr double kStrongReflectionLevelDb = -14.0;

// The RSAO's strong reflections, relative to its direct sound.
std::vector<RelativeReflection> strongEarlyReflections(const Rsao& rsao);

// Whether a specular path (not the direct sound) arrives within 0.6 ms of the reflection,
// counted from its own direct sound, and within 30 degrees of its direction.
bool explainedBySpecularPath(const std::vector<SpecularPath>& paths, const RelativeReflection& reflection);

// A strong reflection no specular path explains, placed by image-source geometry: the
// point P on the arrival ray from the receiver R whose path from the source S is the
// reflection's length L (|S - P| + |P - R| = L):
//   P = R + d u,  d = (L^2 - |S - R|^2) / (2 (L - u . (S - R))),
// reflecting with the normal that bisects the directions from P to S and to R.
struct UnexplainedReflection {
  Eigen::Vector3d point, normal;
  double level_db = 0.0;  // re the direct sound
};

// The strong reflections of `rsao` that no path explains and whose point lies inside the
// room, 0.3 m or more from its surfaces. A point outside the room or on a surface is one
// the model has (its reflection mistimed, or of a higher order than its image sources,
// or two coincident ones the RSAO merged into one direction), not a missing surface.
std::vector<UnexplainedReflection> unexplainedReflections(const Rsao& rsao, const std::vector<SpecularPath>& paths,
                                                          const MeasurementPair& pair, const AcousticScene& scene,
                                                          double speed_of_sound_m_s);

}  // namespace room_reverb::core
