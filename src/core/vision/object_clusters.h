#pragma once
// Furniture candidates as connected groups of occupied voxels.
//
// Connected components on the voxel grid the layout fit already has, rather than PCL's
// EuclideanClusterExtraction: it needs no k-d tree (a hash lookup per neighbour, linear
// in the number of voxels), gives about the clusters of a Euclidean tolerance of `reach`
// voxels, and keeps PCL out of the core library's link line.
#include <cstdint>
#include <vector>

#include "voxel_grid.h"

namespace room_reverb::core::layout {

// Groups of candidate voxels linked through neighbours up to `reach` cells away along
// each axis (reach 1: the 26 neighbours; reach 2 also bridges a one-voxel gap, as a far
// object's sparse points leave), largest first; groups of fewer than min_voxels voxels
// are dropped.
std::vector<std::vector<std::uint32_t>> connectedVoxelClusters(const VoxelGrid& grid,
                                                               const std::vector<bool>& candidate,
                                                               std::size_t min_voxels, int reach);

}  // namespace room_reverb::core::layout
