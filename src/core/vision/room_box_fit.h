#pragma once
// The room box in the aligned frame (the rig at the origin, x and y along the walls, z
// up): floor and ceiling heights and the four walls, found as peaks of histograms of the
// points' coordinates along each face's normal and refined as weighted medians.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "plane_histogram.h"

namespace room_reverb::core::layout {

struct BoxFitParams {
  PlaneSpread spread;
  double bin_m = 0.01;                     // histogram resolution
  double min_plane_support = 200.0;        // voxels (area / voxel^2) a plane needs at least
  double min_plane_contrast = 3.0;         // see PlaneHistogram::peaks
  double outer_plane_fraction = 0.3;       // see findHorizontalPlanes / findWallPair
  double ceiling_min_support_fraction = 0.15;
  double band_margin_m = 0.2;              // wall histograms skip this much next to floor and ceiling
};

struct HorizontalPlanes {
  double floor_z = 0.0;
  double floor_support = 0.0;
  bool has_ceiling = false;
  double ceiling_z = 0.0;
  double ceiling_support = 0.0;
};

// Floor: among the planes below the rig, the lowest one with at least outer_plane_fraction
// of the strongest one's support (a large bed or table top is weaker than the floor and
// higher; sparse outliers below the floor make no plane). Ceiling: likewise the highest
// plane above the rig, if the strongest plane there has at least
// ceiling_min_support_fraction of the floor's support; otherwise the room has no ceiling
// (a courtyard: only furniture tops or nothing above). Throws InputError if there is no
// floor.
HorizontalPlanes findHorizontalPlanes(const std::vector<double>& z, const BoxFitParams& params);

// Two walls along one axis. On each side of the rig, the candidates are the planes with
// at least outer_plane_fraction of that side's strongest plane's support (area, from the
// voxel centroids `voxel_coordinate`); the wall is the innermost candidate that stops
// more of the rig's rays than get past it (ray counts from the raw points'
// `ray_coordinate`). A sideboard's front stops fewer rays than the wall behind it; a wall
// with a window stops more than the window lets through, however large the facade seen
// through it looks in area. If no candidate qualifies, the outermost one. Throws
// InputError naming the axis if a side has no plane.
struct WallPair {
  double lo = 0.0, hi = 0.0;
};
WallPair findWallPair(const std::vector<double>& voxel_coordinate, const std::vector<double>& ray_coordinate,
                      const BoxFitParams& params, const char* axis);

struct AlignedBox {
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0, y_hi = 0.0;
  double floor_z = 0.0, top_z = 0.0;  // top_z: the ceiling, or the walls' top without one
  bool has_ceiling = true;
  std::array<double, 6> support{};  // voxels (area / voxel^2) on each face, kRoomSurfaceNames order

  // How close to a face a point may be and still be taken as lying on it: the face's
  // window (see PlaneSpread) at its distance from the rig.
  double margin(int face, const PlaneSpread& spread) const;
  double facePosition(int face) const;
};

// A raw point in the aligned frame, weighted by one over the number of points in its
// voxel (so that a patch of surface weighs the same near and far from the rig).
struct WeightedPoint {
  Eigen::Vector3f p = Eigen::Vector3f::Zero();
  float weight = 0.0f;
};

// Walls from peaks of the voxel centroids' histograms (`voxels`, aligned frame), then
// refined as weighted medians of the raw points (`raw`) in centred windows, each wall's
// points taken only between the two walls across it so that corners do not pull it
// inwards; floor and ceiling refined likewise from the points between the walls.
// `planes` are the coarse horizontal planes. The top of a room without a ceiling is left
// at the highest point; see wallTopEdge.
AlignedBox fitAlignedBox(const std::vector<Eigen::Vector3d>& voxels, const std::vector<WeightedPoint>& raw,
                         const HorizontalPlanes& planes, const BoxFitParams& params);

// Top of the walls of a room without a ceiling: the height where the density of the raw
// points in the walls' windows (area-weighted, see WeightedPoint) drops to half of its
// level below. Half-height of a blurred step is where the step is, for any symmetric blur.
double wallTopEdge(const std::vector<WeightedPoint>& raw, const AlignedBox& box, const PlaneSpread& spread);

}  // namespace room_reverb::core::layout
