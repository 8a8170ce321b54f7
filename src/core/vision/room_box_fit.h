#pragma once
// The room box in the aligned frame (the rig at the origin, x and y along the walls, z
// up): floor and ceiling heights and the four walls, found as peaks of histograms of the
// points' coordinates along each face's normal and refined as weighted medians.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "plane_histogram.h"
#include "surface_edge.h"

namespace room_reverb::core::layout {

struct BoxFitParams {
  PlaneSpread spread;
  double bin_m = 0.01;                     // histogram resolution
  double min_plane_support = 200.0;        // voxels (area / voxel^2) a plane needs at least
  double min_plane_contrast = 3.0;         // see PlaneHistogram::peaks
  // A wall is rarely one plane: a recessed door or window, a radiator, skirting and the
  // furniture against it make layers a few centimetres to decimetres apart, each of which
  // shows less contrast than a plain wall (a real kitchen's door wall: 1.5 and 2.1). Layers
  // of this contrast are wall candidates where the ceiling's or floor's edge confirms them.
  double min_layer_contrast = 1.4;
  double edge_tolerance_m = 0.2;   // a wall plane lies within this of the ceiling's edge
  double hidden_wall_m = 0.5;      // planes further inside the edge are in front of the wall
  double layer_gap_m = 0.25;       // layers within this of the outermost are one wall
  double min_layer_coverage = 0.3;  // a faint layer covers this fraction of the room's length
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

// What a wall's position rests on (see findWallPair).
enum class WallBasis {
  kPlaneAtEdge,  // a dense vertical plane where the ceiling or floor ends
  kPlane,        // a dense vertical plane, no horizontal surface's edge to confirm it
  kEdge,         // the ceiling's or floor's edge; the wall itself is hidden or cluttered
  kRayStop,      // beyond the ceiling's ranged edge, where the rays aimed past it stop (ray_stops.h)
  kOpen,         // nothing stands where the floor ends: an open side
  kScatteredPlane,  // where the floor ends, a plane whose points scatter beyond the calibrated noise
  kCeilingJunction,  // where the image shows the ceiling meeting it (wall_junctions.h)
};

struct WallChoice {
  double position_m = 0.0;  // signed, along the axis
  WallBasis basis = WallBasis::kPlane;
  double confidence = 0.0;  // 0..1
  double contrast = 0.0;    // of the chosen plane (0 without one)
};

// Two walls along one axis. `edges[0]` and `edges[1]` are where the ceiling or floor
// ends on the low and high side (surface_edge.h), if known; `edge_from_ceiling` says
// whether that edge is the ceiling's (a ceiling always ends at a wall; the ground of a
// courtyard may run on past an open side).
//
// With a step at the edge, the candidates are the planes of at least min_layer_contrast
// (and covering at least min_layer_coverage of the room's length along the wall, if below
// min_plane_contrast) up to edge_tolerance_m beyond it, and those up to hidden_wall_m
// beyond it that cover at least three quarters of the room's length the edge's own layer
// covers and hold a quarter of its points (wall units or a wardrobe reaching the ceiling
// end it in front of the wall, which shows along the run; a recess's back or a facade
// seen through a window shows only across the opening); with no layer at the edge, those
// of at least min_plane_contrast up to hidden_wall_m beyond it. If the outermost
// candidate lies within hidden_wall_m of the edge, the wall is the candidate with the most
// support among the layers within layer_gap_m of the outermost one and no further inside
// the edge than edge_tolerance_m (the main wall plane, not the back of a door recess in
// it, a radiator in front of it, or units along it under a ceiling that goes on past
// them); otherwise the planes are furniture in front of a hidden wall and the wall is the
// edge.
//
// Without a step (the surface thins out with range, as a far wall's ceiling does, or no
// surface on that side), the candidates are the planes of at least min_plane_contrast with at
// least outer_plane_fraction of that side's strongest plane's support (area, from the
// voxel centroids `voxel_coordinate`); the wall is the innermost candidate that stops
// more of the rig's rays than get past it (ray counts from the raw points'
// `ray_coordinate`). A sideboard's front stops fewer rays than the wall behind it; a wall
// with a window stops more than the window lets through, however large the facade seen
// through it looks in area. If no candidate qualifies, the outermost one. With no such
// plane either, the surface's farthest point: an open side if nothing stands there and the
// surface is the ground, else a wall hidden there. Where the ground ends with no layer
// there, a plane whose points scatter two, four or eight times the calibrated noise is sought
// about the edge before the side is taken for open (scatteredWallAtEdge).
//
// Throws InputError naming the side if a side has neither a plane nor a surface.
struct WallPair {
  WallChoice lo, hi;
};
// The voxels between the floor's and the ceiling's windows, seen along one wall axis.
struct WallBand {
  std::vector<double> coordinate;  // along the axis
  std::vector<double> lateral;     // along the walls of that axis
  std::vector<double> height;      // z
  double z_lo = 0.0, z_hi = 0.0;   // the band's limits (z_hi infinite without a ceiling)
};
WallPair findWallPair(const WallBand& band, const std::vector<double>& ray_coordinate,
                      const std::array<std::optional<SurfaceEdge>, 2>& edges, bool edge_from_ceiling,
                      const BoxFitParams& params, const char* axis);

struct AlignedBox {
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0, y_hi = 0.0;
  double floor_z = 0.0, top_z = 0.0;  // top_z: the ceiling, or the walls' top without one
  bool has_ceiling = true;
  std::array<double, 6> support{};  // voxels (area / voxel^2) on each face, kRoomSurfaceNames order
  std::array<WallChoice, 6> choice{};  // what each face rests on (floor and ceiling: kPlane)

  // How close to a face a point may be and still be taken as lying on it: the face's
  // window (see PlaneSpread) at its distance from the rig. Inline: the fit asks it for
  // every point of the cloud.
  double margin(int face, const PlaneSpread& spread) const { return spread.halfWidth(facePosition(face)); }
  double facePosition(int face) const {
    switch (face) {
      case 0: return floor_z;
      case 1: return top_z;
      case 2: return x_lo;
      case 3: return x_hi;
      case 4: return y_lo;
      default: return y_hi;
    }
  }
};

// A raw point in the aligned frame, weighted by one over the number of points in its
// voxel (so that a patch of surface weighs the same near and far from the rig).
struct WeightedPoint {
  Eigen::Vector3f p = Eigen::Vector3f::Zero();
  float weight = 0.0f;
};

// Walls from peaks of the voxel centroids' histograms (`voxels`, aligned frame; a wall
// findWallPair places at the ceiling's edge moves out to where the rays aimed past that
// edge stop, when they stop beyond it: wallWhereCeilingRaysStop), then
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
