#include "voxel_grid.h"

#include <cmath>

namespace room_reverb::core::layout {

VoxelGrid::VoxelGrid(const PointCloud& cloud, double voxel_size_m, double max_range_m) : size_(voxel_size_m) {
  const std::size_t n = cloud.points.size();
  point_voxel_.assign(n, kNoVoxel);
  index_ = CellIndex(n / 8 + 16);
  std::vector<std::uint32_t> structure_votes, object_votes;
  const double inv = 1.0 / voxel_size_m;
  const double max_range2 = max_range_m * max_range_m;
  Eigen::Vector3i last_cell = Eigen::Vector3i::Zero();
  std::uint32_t last_voxel = kNoVoxel;
  for (std::size_t i = 0; i < n; ++i) {
    const CloudPoint& point = cloud.points[i];
    const Eigen::Vector3d p = point.p.cast<double>();
    if (p.squaredNorm() > max_range2) continue;
    const Eigen::Vector3i cell((p * inv).array().floor().cast<int>());
    // A cloud from a range image lists its points pixel by pixel, and neighbouring pixels
    // mostly fall in one voxel: the last one is asked before the index.
    std::uint32_t v = last_voxel;
    if (v == kNoVoxel || cell != last_cell) {
      const auto [found, inserted] = index_.insert(cell, static_cast<std::uint32_t>(voxels_.size()));
      if (inserted) {
        voxels_.push_back({cell, Eigen::Vector3d::Zero(), 0, VoxelHint::unknown});
        structure_votes.push_back(0);
        object_votes.push_back(0);
      }
      v = found, last_voxel = found, last_cell = cell;
    }
    point_voxel_[i] = v;
    voxels_[v].centroid += p;  // a sum until the loop ends
    ++voxels_[v].count;
    const auto hint = static_cast<SurfaceHint>(point.hint);
    if (hint == SurfaceHint::floor || hint == SurfaceHint::ceiling || hint == SurfaceHint::wall) ++structure_votes[v];
    if (hint == SurfaceHint::object) ++object_votes[v];
  }
  for (std::size_t v = 0; v < voxels_.size(); ++v) {
    Voxel& voxel = voxels_[v];
    voxel.centroid /= static_cast<double>(voxel.count);
    if (2 * structure_votes[v] > voxel.count) voxel.hint = VoxelHint::structure;
    if (2 * object_votes[v] > voxel.count) voxel.hint = VoxelHint::object;
  }
}

std::uint32_t VoxelGrid::find(const Eigen::Vector3i& cell) const { return index_.find(cell); }

}  // namespace room_reverb::core::layout
