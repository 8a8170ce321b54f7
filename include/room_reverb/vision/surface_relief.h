#pragma once
// The relief of each face and object of a fitted room from the cloud it was fitted to:
// what stands on a wall, the floor or the ceiling, or is set into it, and what an
// object's box does not follow (the gap under a worktop, shelves' contents, a table and
// its chairs held in one box). A room model of smooth boxes keeps the specular field of
// an empty room: in a furnished room whose absorption sits on a few faces (a tile ceiling
// above hard walls), rays that run between the hard walls outlive the rest and the
// model's decay is several times the room's. The relief scatters them.
//
// Each face is cut into square cells; a cell's height is the median height of the
// cloud's points there above the face (into the room; negative behind it): 0 for points
// on the face (within the layout's face margin, RoomLayout::point_surface), their distance
// from its plane for points off every face and object up to max_height_m. An object's
// points are measured from the face of its box the rig sees them through (negative
// inside it; on the face within the layout's face margin at their range), each face from
// its points' median (a box fitted proud of what it holds is a plane moved), and the
// object's relief is its faces' together. Cells that no point reaches are left out. The seen cells' heights give
// the scattering per band (acoustics/relief_scattering.h).
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <vector>

#include "room_reverb/vision/point_cloud.h"
#include "room_reverb/vision/room_layout.h"

namespace room_reverb::core {

struct SurfaceReliefOptions {
  bool enabled = true;
  double cell_m = 0.1;                  // edge of a face's cells [m]
  std::size_t min_points_per_cell = 3;  // fewer: the cell is not seen
  // Points farther from every face than this [m] stand free in the room (a chair, a
  // person): not a face's relief. Deep enough for a worktop (0.6 m) or a bookcase.
  double max_height_m = 0.6;
  // A face or object with less seen area than this [m^2] gets no relief (too little to
  // judge; a small object scatters by its size, which the simulation's diffraction
  // scattering models).
  double min_seen_m2 = 0.5;
  double speed_of_sound_m_s = 343.0;
};

struct SurfaceReliefs {
  std::array<ReliefEstimate, 6> faces{};  // kRoomSurfaceNames order
  std::vector<ReliefEstimate> objects;    // layout.model.objects order
};

// `room_from_cloud` takes the cloud's points into the room frame (RoomLayout::
// room_from_rig for the cloud the layout was fitted from); the layout must carry
// point_surface and point_object for this cloud (RoomLayoutOptions::assign_points), and
// `layout_options` are the fit's (its face margins). InputError for options out of range
// or a layout whose point labels do not match the cloud.
SurfaceReliefs estimateSurfaceRelief(const PointCloud& cloud, const RoomLayout& layout,
                                     const Eigen::Isometry3d& room_from_cloud, const RoomLayoutOptions& layout_options,
                                     const SurfaceReliefOptions& options = {});

// Stores the estimates in layout.face_relief and layout.object_relief, and each estimated
// one's scattering as its face's or object's relief_scattering in layout.model.
void applySurfaceRelief(RoomLayout& layout, const SurfaceReliefs& relief);

}  // namespace room_reverb::core
