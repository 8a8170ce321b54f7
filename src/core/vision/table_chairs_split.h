#pragma once
// A table and the chairs around it, which the stereo's smear and the seats pushed in under
// the top link into one voxel cluster: one cuboid over all of them is a solid block the
// size of the dining area.
//
// The table top is the horizontal layer, between knee and chest height, that holds the
// most of the cluster's points; its plan is the largest patch of that layer (a top seen at
// a slant shows as rows of points with gaps between; the backs of chairs also cross the
// layer, a hand's width or more from the top's edge). It is a table only if little stands
// under it (legs, the seats of chairs pushed in) and little rises above it: a worktop, a
// cabinet's top, a sofa's back have their body under them, and a top whose patch runs
// into a wardrobe's front has the front above it; they are left whole. The points standing outside the
// top's plan (grown by a cell) are the chairs, each group linked across at most a cell
// and a half its own piece; smaller groups stay with the table. What stands under the top
// near a chair (its seat and legs, pushed in) goes with that chair. A group larger than a
// chair means the cluster is something else (a worktop with wall units over it).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace room_reverb::core::layout {

struct TableSplitParams {
  double low_m = 0.55, high_m = 1.15;  // the heights a table top may have [m]
  // At most this share of the top layer's voxel count may stand under the top, lower than
  // clearance_m [m] below it, and as much above it, higher than clearance_m above it.
  double max_under_fraction = 0.35;
  double clearance_m = 0.15;
  std::size_t min_voxels = 30;  // a smaller group is no chair
  // A group beside the top wider [m] or taller [m] than a chair is no chair, and the
  // cluster no table with chairs (a worktop's wall units, a fridge).
  double max_chair_extent_m = 0.9, max_chair_height_m = 1.3;
  // What stands under the top within this distance [m] of a chair's plan is that chair's
  // seat and legs, pushed in under the table's edge.
  double pushed_in_reach_m = 0.3;
  double seat_low_m = 0.3;  // ... from this height up: lower, the table's legs stay its
};

struct TableSplit {
  std::vector<std::vector<std::uint32_t>> tables_and_chairs;  // the pieces of every table cut
  std::vector<std::vector<std::uint32_t>> rest;               // the clusters no table was found in
  std::vector<std::size_t> rest_index;                        // each one's index in the input
};

// `room_centroid[v]`: voxel v's position in the room frame; cell_m the voxel size.
TableSplit splitTablesFromChairs(const std::vector<std::vector<std::uint32_t>>& clusters,
                                 const std::vector<Eigen::Vector3d>& room_centroid, double cell_m,
                                 const TableSplitParams& params);

}  // namespace room_reverb::core::layout
