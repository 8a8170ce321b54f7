#pragma once
// The furniture step of the layout fit: clusters of voxels clear of the room's faces,
// merged where they overlap, each turned into a labelled cuboid.
#include <cstdint>
#include <vector>

#include "cuboid_fit.h"
#include "hidden_sides.h"
#include "room_frame.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/vision/point_cloud.h"
#include "voxel_grid.h"

namespace room_reverb::core::layout {

struct FurnitureParams {
  CuboidFitParams cuboid;
  HiddenSideParams hidden;
  std::size_t min_voxels = 30;
  int link_voxels = 2;  // see connectedVoxelClusters
  double min_extent_m = 0.15;
  // Two clusters whose cuboids share this fraction of the smaller one's volume are one
  // object (a table top and its front seen apart through a sparse row of points).
  double merge_overlap = 0.25;
};

struct Furniture {
  std::vector<CuboidObject> objects;  // material empty; label, confidence set
  std::vector<std::int32_t> voxel_object;  // per voxel: index into objects, or -1
};

Furniture fitFurniture(const PointCloud& cloud, const VoxelGrid& grid, const RoomFrame& frame,
                       const FurnitureParams& params);

}  // namespace room_reverb::core::layout
