#pragma once
// Furniture clusters that are several pieces standing side by side or one above another:
// a kitchen's base run, the fridge at its end and the wall units above it touch, or come
// within the stereo's smear of each other, and link into one voxel cluster that one
// cuboid would fit badly (the base run as tall as the fridge, the space between worktop
// and wall units solid).
//
// Two cuts, each where the cluster's own shape shows a change of piece:
// - a step: along the cluster's longer horizontal axis, the height of its top (seen from
//   the rig above most furniture, the best-observed part of it) jumps by at least step_m
//   and stays there. A table with chairs, a sofa with its arms, shelving with books keep
//   one top within that.
// - a stack: between the cluster's points there is a horizontal band at least
//   stack_gap_m high that holds none of them, across the whole piece. Shelving (its side
//   boards), tables and chairs (their legs) and wardrobes (their fronts) have points at
//   every height; wall units above a worktop leave the splashback's band empty.
// Pieces smaller than min_voxels stay with their neighbour. The caller joins again what
// the cut separated wrongly (the base run either side of the wall units).
#include <cstdint>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "voxel_grid.h"

namespace room_reverb::core::layout {

struct ProfileSplitParams {
  double step_m = 0.3;       // 0: no cut at steps
  double stack_gap_m = 0.4;  // 0: no cut at stacks
  std::size_t min_voxels = 30;
};

// The clusters (voxel indices) cut as above; `boxes[k]` is cluster k's fitted cuboid
// (its yaw sets the axes), `room_centroid[v]` voxel v's position in the room frame.
std::vector<std::vector<std::uint32_t>> splitClustersAtStepsAndStacks(
    const std::vector<std::vector<std::uint32_t>>& clusters, const std::vector<CuboidObject>& boxes,
    const std::vector<Eigen::Vector3d>& room_centroid, double cell_m, const ProfileSplitParams& params);

}  // namespace room_reverb::core::layout
