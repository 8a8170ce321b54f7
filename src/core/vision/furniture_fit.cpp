#include "furniture_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>

#include "furniture_labels.h"
#include "object_clusters.h"
#include "room_reverb/vision/oriented_box_iou.h"

namespace room_reverb::core::layout {

namespace {

using Clusters = std::vector<std::vector<std::uint32_t>>;

// Confidence of an object [0, 1]: how much of it was seen (saturating in its voxels), and
// half as much if no size rule named it.
double objectConfidence(std::size_t voxels, const std::string& label) {
  const double seen = 1.0 - std::exp(-static_cast<double>(voxels) / 100.0);
  return label == "object" ? 0.5 * seen : seen;
}

// A long side within 2 cm of a wall (two footprint corners on it).
bool againstWall(const CuboidObject& box, const Eigen::Vector3d& size) {
  const auto corners = cuboidFootprint(box);
  const std::array<std::pair<int, double>, 4> walls = {{{0, 0.0}, {0, size.x()}, {1, 0.0}, {1, size.y()}}};
  for (const auto& [axis, at] : walls) {
    int touching = 0;
    for (const auto& c : corners) touching += std::abs(c[axis] - at) <= 0.02;
    if (touching >= 2) return true;
  }
  return false;
}

// The fraction of the smaller box's volume inside the other.
double sharedFraction(const CuboidObject& a, const CuboidObject& b) {
  const double va = a.size_m.prod(), vb = b.size_m.prod();
  if (va <= 0.0 || vb <= 0.0) return 0.0;
  const double iou = orientedBoxIoU3d(a, b);
  return iou * (va + vb) / (1.0 + iou) / std::min(va, vb);
}

std::size_t root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// The clusters with every pair whose boxes share merge_overlap of the smaller one's
// volume joined (transitively).
Clusters mergedClusters(const Clusters& clusters, const std::vector<CuboidObject>& boxes, double merge_overlap) {
  std::vector<std::size_t> parent(clusters.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t a = 0; a < clusters.size(); ++a) {
    for (std::size_t b = a + 1; b < clusters.size(); ++b) {
      if (sharedFraction(boxes[a], boxes[b]) >= merge_overlap) parent[root(parent, b)] = root(parent, a);
    }
  }
  Clusters groups(clusters.size());
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    auto& into = groups[root(parent, k)];
    into.insert(into.end(), clusters[k].begin(), clusters[k].end());
  }
  groups.erase(std::remove_if(groups.begin(), groups.end(), [](const auto& g) { return g.empty(); }), groups.end());
  return groups;
}

// Fits a cuboid to each cluster: its raw points (room frame, clear of the room's faces),
// then its hidden sides carved against every other voxel the rig saw in the room.
class ClusterFitter {
 public:
  ClusterFitter(const PointCloud& cloud, const VoxelGrid& grid, const RoomFrame& frame, const FurnitureParams& params)
      : cloud_(cloud), grid_(grid), frame_(frame), params_(params) {
    const auto& voxels = grid.voxels();
    room_centroid_.resize(voxels.size());
    for (std::size_t v = 0; v < voxels.size(); ++v) room_centroid_[v] = frame.toRoom(voxels[v].centroid);
    // Points beyond the walls are strays or seen through windows: their rays prove nothing.
    for (std::uint32_t v = 0; v < voxels.size(); ++v) {
      if (frame.inside(room_centroid_[v])) seen_.push_back(v);
    }
  }

  const std::vector<Eigen::Vector3d>& roomCentroids() const { return room_centroid_; }

  // Boxes of the clusters (a zero box for a cluster without points); sets voxel_cluster.
  std::vector<CuboidObject> fit(const Clusters& clusters, std::vector<std::int32_t>& voxel_cluster) const {
    voxel_cluster.assign(grid_.voxels().size(), -1);
    for (std::size_t k = 0; k < clusters.size(); ++k) {
      for (std::uint32_t v : clusters[k]) voxel_cluster[v] = static_cast<std::int32_t>(k);
    }
    std::vector<std::vector<Eigen::Vector3d>> points(clusters.size());
    for (std::size_t i = 0; i < cloud_.points.size(); ++i) {
      const std::uint32_t v = grid_.pointVoxel()[i];
      if (v == VoxelGrid::kNoVoxel || voxel_cluster[v] < 0) continue;
      const Eigen::Vector3d p = frame_.toRoom(cloud_.points[i].p.cast<double>());
      if (frame_.clearOfFaces(p)) points[voxel_cluster[v]].push_back(p);
    }
    std::vector<CuboidObject> boxes(clusters.size());
    std::vector<Eigen::Vector3d> elsewhere;
    for (std::size_t k = 0; k < clusters.size(); ++k) {
      if (points[k].empty()) continue;
      elsewhere.clear();
      for (std::uint32_t v : seen_) {
        if (voxel_cluster[v] != static_cast<std::int32_t>(k)) elsewhere.push_back(room_centroid_[v]);
      }
      const CuboidObject seen_part = fitCuboid(points[k], params_.cuboid);
      boxes[k] = normalisedCuboid(extendHiddenSides(seen_part, elsewhere, params_.hidden));
    }
    return boxes;
  }

 private:
  const PointCloud& cloud_;
  const VoxelGrid& grid_;
  const RoomFrame& frame_;
  const FurnitureParams& params_;
  std::vector<Eigen::Vector3d> room_centroid_;
  std::vector<std::uint32_t> seen_;
};

}  // namespace

Furniture fitFurniture(const PointCloud& cloud, const VoxelGrid& grid, const RoomFrame& frame,
                       const FurnitureParams& params) {
  const auto& voxels = grid.voxels();
  const ClusterFitter fitter(cloud, grid, frame, params);
  std::vector<bool> candidate(voxels.size(), false);
  for (std::size_t v = 0; v < voxels.size(); ++v) {
    candidate[v] = voxels[v].hint != VoxelHint::structure && frame.clearOfFaces(fitter.roomCentroids()[v]);
  }
  Clusters clusters = connectedVoxelClusters(grid, candidate, params.min_voxels, params.link_voxels);
  std::vector<std::int32_t> voxel_cluster;
  std::vector<CuboidObject> boxes = fitter.fit(clusters, voxel_cluster);
  // Clusters whose cuboids overlap are parts of one object seen in pieces: fitted again
  // as one.
  Clusters merged = mergedClusters(clusters, boxes, params.merge_overlap);
  if (merged.size() < clusters.size()) {
    clusters = std::move(merged);
    boxes = fitter.fit(clusters, voxel_cluster);
  }

  Furniture furniture;
  std::vector<std::int32_t> cluster_object(clusters.size(), -1);
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    CuboidObject object = boxes[k];
    if (object.size_m.maxCoeff() < params.min_extent_m || (object.size_m.array() <= 0.0).any()) continue;
    const bool on_floor = object.center_m.z() - 0.5 * object.size_m.z() <= 1e-9;
    object.label = furnitureLabel(object, on_floor, againstWall(object, frame.size));
    object.material = "";  // placeholder: the material step names it
    object.confidence = objectConfidence(clusters[k].size(), object.label);
    cluster_object[k] = static_cast<std::int32_t>(furniture.objects.size());
    furniture.objects.push_back(object);
  }
  furniture.voxel_object.assign(voxels.size(), -1);
  for (std::size_t v = 0; v < voxels.size(); ++v) {
    if (voxel_cluster[v] >= 0) furniture.voxel_object[v] = cluster_object[voxel_cluster[v]];
  }
  return furniture;
}

}  // namespace room_reverb::core::layout
