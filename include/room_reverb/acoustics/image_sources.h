#pragma once
// The image-source method for any polygonal room (Allen & Berkley 1979 for the idea;
// Borish 1984 for arbitrary polyhedra): mirror the source in every plane up to a maximum
// order, and keep an image only if the path it stands for is real: each reflection point
// lies on a triangle of its plane and nothing blocks any leg (checked with Embree rays).
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/propagation.h"

namespace room_reverb::core {

struct ImageSourceOptions {
  int max_order = 3;
  // Scale each reflection by the specular share sqrt(1 - s) of the surface's scattering;
  // the scattered share is the ray tracer's (no energy is counted twice).
  bool specular_share_only = true;
  // With specular_share_only: the specular share also loses what the surface's finite size
  // diffracts away (diffraction_scattering.h), each reflection with the unfolded distances
  // from the source and to the listener as its d1 and d2.
  bool diffraction_scattering = false;
  // The search visits about planes x branching^(order - 1) candidate images: in the
  // sample room's 28 planes order 6 (estimated 7e7 candidates) takes 13 s and order 7
  // (1.3e9) over 3 minutes. An order whose estimated count exceeds this (about half a
  // minute at that rate) is refused up front with an error naming the highest order that
  // fits.
  double max_candidates = 2e8;
  // In a scene built from a room model (its objects known as cuboids): the direct sound
  // blocked by an object is heard around the object's nearest edge, weaker and duller
  // (edge_diffraction.h), instead of not at all; one heard close to an object's shadow
  // is weakened as it approaches it, so that crossing the shadow's edge changes nothing
  // abruptly. Scenes from meshes keep the plain visibility test.
  bool diffract_direct_sound = true;
};

// The number of candidate images the search visits up to `order`: counted exactly to
// order 3, and beyond by the growth of the last counted order (the mean number of planes
// an image sees on the listener's side).
double estimatedImageCandidates(const AcousticScene& scene, const Eigen::Vector3d& source,
                                const Eigen::Vector3d& listener, int order);

struct SpecularPath {
  int order = 0;                        // 0: the direct sound
  Eigen::Vector3d image_position = Eigen::Vector3d::Zero();     // m, room frame
  double distance_m = 0.0;              // unfolded path length
  double delay_s = 0.0;                 // distance / c
  OctaveBandValues pressure_gain{};     // per band: directivity, reflections, 1/r, air
  Eigen::Vector3d arrival_direction = Eigen::Vector3d::UnitX();  // unit, from the listener towards where it comes from
  std::vector<std::size_t> triangles;   // hit triangle of each reflection, source side first
};

// Whether the specular path from `source` by reflections in `planes` (indices into
// scene.planes(), source side first) to `listener` is real, by the test
// computeImageSources applies: each (image) source and the listener on the same side of
// the next plane, each reflection point on a triangle of its plane, no leg blocked. For a
// listener that moves along known paths, without searching every image again.
bool specularPathValid(const AcousticScene& scene, const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                       const std::vector<std::size_t>& planes);
// The same test; where the path is real, its reflection points (one per plane, source side
// first), else nothing: what a viewer draws of a reflection.
std::optional<std::vector<Eigen::Vector3d>> specularReflectionPoints(const AcousticScene& scene,
                                                                     const Eigen::Vector3d& source,
                                                                     const Eigen::Vector3d& listener,
                                                                     const std::vector<std::size_t>& planes);
// A computed path's polyline: `source`, its reflection points (from the planes of its
// triangles), `listener`; nothing where it is not valid between these two.
std::optional<std::vector<Eigen::Vector3d>> specularPathPoints(const AcousticScene& scene, const Eigen::Vector3d& source,
                                                               const Eigen::Vector3d& listener, const SpecularPath& path);

// Pressure gains are relative to the direct sound of an omni source at 1 m (gain 1).
std::vector<SpecularPath> computeImageSources(const AcousticScene& scene, const Eigen::Vector3d& source,
                                              const Eigen::Vector3d& listener, const PropagationModel& model,
                                              const ImageSourceOptions& options = {});

}  // namespace room_reverb::core
