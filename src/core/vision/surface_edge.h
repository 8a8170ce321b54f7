#pragma once
// Where a horizontal surface (the ceiling, the floor) ends on one side of the rig: the
// outer edge of the band of its points, read along one wall direction. The ceiling runs
// to the walls over the furniture that hides their lower part, so its edge says where a
// wall is even when the wall shows several layers (a recessed door, a kitchen run, a
// radiator) or hardly any plane (shelving full of clutter).
#include <optional>
#include <vector>

namespace room_reverb::core::layout {

// A step must drop the density to at most 1/kStepRatio of what it was just inside, from a
// level of at least kMinSurfaceLevel of the surface's typical density.
constexpr double kStepRatio = 3.0;
constexpr double kMinSurfaceLevel = 0.1;

// `distances`: how far each of the surface's points (voxel centroids, so area-weighted)
// lies from the rig along the direction, all on one side (non-negative). The edge is the
// innermost place where the density of points per unit distance steps down (over
// `step_span_m` either side) to a fraction of what it was and never comes back to half of
// it further out: far away a surface thins out gradually as the rig's rays spread over it,
// which is no step; a light's shadow is a step the ceiling comes back from; strays and a
// facade seen through a window beyond the wall are too thin to come back. Without a step
// (a surface seen thinning out to the farthest ranges), `distance_m` is its farthest point
// before the first empty stretch of a tenth of its distance (at least 1 m; strays lie
// beyond) and `step` false. nullopt with fewer than `min_points` points.
struct SurfaceEdge {
  double distance_m = 0.0;
  bool step = true;
};
std::optional<SurfaceEdge> surfaceEdge(const std::vector<double>& distances, double bin_m = 0.05, double step_span_m = 0.3,
                                  std::size_t min_points = 40);

}  // namespace room_reverb::core::layout
