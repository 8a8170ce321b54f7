#pragma once
// A sparse voxel grid over a point cloud: the room layout fit works on voxel centroids,
// not raw points, because stereo clouds are far denser near the rig than far from it
// (density falls with the square of the range). One centroid per occupied voxel makes a
// plane's support proportional to its area, which is what "the dominant plane" means, and
// cuts a million points down to tens of thousands.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "cell_index.h"
#include "room_reverb/vision/point_cloud.h"

namespace room_reverb::core::layout {

// What most of a voxel's points are hinted to be (SurfaceHint folded into three classes).
enum class VoxelHint : std::uint8_t { unknown, structure, object };

struct Voxel {
  Eigen::Vector3i cell = Eigen::Vector3i::Zero();  // integer cell: floor(p / size)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // mean of its points, cloud frame
  std::uint32_t count = 0;
  VoxelHint hint = VoxelHint::unknown;
};

class VoxelGrid {
 public:
  static constexpr std::uint32_t kNoVoxel = CellIndex::kNone;

  // Points farther than max_range_m from the origin (the rig) are left out: a stereo
  // matcher reports the sky and textureless glass at arbitrary, huge depths.
  VoxelGrid(const PointCloud& cloud, double voxel_size_m, double max_range_m);

  double size() const { return size_; }
  const std::vector<Voxel>& voxels() const { return voxels_; }
  // Voxel of each input point, kNoVoxel for points left out.
  const std::vector<std::uint32_t>& pointVoxel() const { return point_voxel_; }
  // Index of the voxel at `cell`, kNoVoxel if it is empty.
  std::uint32_t find(const Eigen::Vector3i& cell) const;

 private:
  double size_;
  std::vector<Voxel> voxels_;
  std::vector<std::uint32_t> point_voxel_;
  CellIndex index_;
};

}  // namespace room_reverb::core::layout
