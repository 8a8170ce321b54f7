#include "object_clusters.h"

#include <algorithm>

#include "cell_index.h"

namespace room_reverb::core::layout {

std::vector<std::vector<std::uint32_t>> connectedVoxelClusters(const VoxelGrid& grid,
                                                               const std::vector<bool>& candidate,
                                                               std::size_t min_voxels, int reach) {
  const auto& voxels = grid.voxels();
  // Only the candidates, in a table of their own: each lookup then stays in cache.
  CellIndex cells;
  for (std::uint32_t v = 0; v < voxels.size(); ++v) {
    if (candidate[v]) cells.insert(voxels[v].cell, v);
  }
  std::vector<bool> visited(voxels.size(), false);
  std::vector<std::vector<std::uint32_t>> clusters;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < voxels.size(); ++seed) {
    if (!candidate[seed] || visited[seed]) continue;
    std::vector<std::uint32_t> cluster;
    visited[seed] = true;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::uint32_t v = stack.back();
      stack.pop_back();
      cluster.push_back(v);
      for (int dx = -reach; dx <= reach; ++dx) {
        for (int dy = -reach; dy <= reach; ++dy) {
          for (int dz = -reach; dz <= reach; ++dz) {
            const std::uint32_t n = cells.find(voxels[v].cell + Eigen::Vector3i(dx, dy, dz));
            if (n == CellIndex::kNone || visited[n]) continue;
            visited[n] = true;
            stack.push_back(n);
          }
        }
      }
    }
    if (cluster.size() >= min_voxels) clusters.push_back(std::move(cluster));
  }
  std::sort(clusters.begin(), clusters.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return clusters;
}

}  // namespace room_reverb::core::layout
