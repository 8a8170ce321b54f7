#pragma once
// The furniture step of the layout fit: clusters of voxels clear of the room's faces,
// split where a thin bridge of stray points joins two pieces (cluster_split.h), joined
// where one piece was seen in parts, each turned into a labelled cuboid.
#include <cstdint>
#include <vector>

#include "cluster_profile_split.h"
#include "cluster_split.h"
#include "cuboid_fit.h"
#include "hidden_sides.h"
#include "room_frame.h"
#include "table_chairs_split.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/vision/point_cloud.h"
#include "voxel_grid.h"

namespace room_reverb::core::layout {

struct FurnitureParams {
  CuboidFitParams cuboid;
  HiddenSideParams hidden;
  ClusterSplitParams split;
  ProfileSplitParams profile;  // min_voxels is this struct's
  TableSplitParams table;      // min_voxels is this struct's
  std::size_t min_voxels = 30;
  int link_voxels = 2;  // see connectedVoxelClusters
  double min_extent_m = 0.15;
  // Two clusters whose cuboids share this fraction of the smaller one's volume are one
  // object (a table top and its front seen apart through a sparse row of points).
  double merge_overlap = 0.25;
  // Two clusters whose points come this close [m] are one object if hardly a ray passes
  // through the cuboid of both: fewer than hidden.free_rays, or than join_stray_fraction
  // of their voxels (see sameObject in furniture_fit.cpp).
  double join_gap_m = 0.25;
  double join_stray_fraction = 0.05;
};

struct Furniture {
  std::vector<CuboidObject> objects;  // material empty; label, confidence set
  std::vector<std::int32_t> voxel_object;  // per voxel: index into objects, or -1
};

Furniture fitFurniture(const PointCloud& cloud, const VoxelGrid& grid, const RoomFrame& frame,
                       const FurnitureParams& params);

}  // namespace room_reverb::core::layout
