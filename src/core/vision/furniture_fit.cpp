#include "furniture_fit.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <string>

#include "cluster_profile_split.h"
#include "furniture_labels.h"
#include "object_clusters.h"
#include "room_reverb/common/parallel_rows.h"
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

// The room-frame bounding boxes of two point sets are within `gap` of each other.
bool near(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double gap) {
  const auto bounds = [](const std::vector<Eigen::Vector3d>& points) {
    Eigen::AlignedBox3d box;
    for (const auto& p : points) box.extend(p);
    return box;
  };
  const Eigen::AlignedBox3d ba = bounds(a), bb = bounds(b);
  return !ba.isEmpty() && !bb.isEmpty() && ba.exteriorDistance(bb) <= gap;
}

// Clusters with what the fit knows of them.
struct Pieces {
  Clusters clusters;                                 // voxel indices
  std::vector<std::int32_t> voxel_cluster;           // per voxel: its cluster or -1
  std::vector<std::vector<Eigen::Vector3d>> points;  // raw points, room frame, clear of the faces
  std::vector<CuboidObject> boxes;                   // fitted, hidden sides extended
  std::vector<std::int32_t> line_owner;              // per line of sight: its voxel's cluster or -1
};

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
    std::vector<Eigen::Vector3d> seen_points;
    for (std::uint32_t v = 0; v < voxels.size(); ++v) {
      if (frame.inside(room_centroid_[v])) seen_.push_back(v), seen_points.push_back(room_centroid_[v]);
    }
    lines_ = SightLines(seen_points, params.hidden);
  }

  const std::vector<Eigen::Vector3d>& roomCentroids() const { return room_centroid_; }

  // The clusters' points and boxes.
  Pieces fit(Clusters clusters) {
    Pieces p;
    p.clusters = std::move(clusters);
    p.voxel_cluster.assign(grid_.voxels().size(), -1);
    for (std::size_t k = 0; k < p.clusters.size(); ++k) {
      for (std::uint32_t v : p.clusters[k]) p.voxel_cluster[v] = static_cast<std::int32_t>(k);
    }
    p.points.assign(p.clusters.size(), {});
    for (std::size_t i = 0; i < cloud_.points.size(); ++i) {
      const std::uint32_t v = grid_.pointVoxel()[i];
      if (v == VoxelGrid::kNoVoxel || p.voxel_cluster[v] < 0) continue;
      const Eigen::Vector3d point = frame_.toRoom(cloud_.points[i].p.cast<double>());
      if (frame_.clearOfFaces(point)) p.points[p.voxel_cluster[v]].push_back(point);
    }
    p.line_owner.resize(seen_.size());
    for (std::size_t i = 0; i < seen_.size(); ++i) p.line_owner[i] = p.voxel_cluster[seen_[i]];
    p.boxes.assign(p.clusters.size(), CuboidObject{});  // a zero box for a cluster without points
    // A cluster's box depends on its own voxels alone (its points, and the lines of sight
    // it owns, which do not carve it): one the merges and cuts left as it was keeps the box
    // an earlier fit gave it.
    std::vector<std::vector<std::uint32_t>> keys(p.clusters.size());
    std::vector<std::size_t> todo;
    for (std::size_t k = 0; k < p.clusters.size(); ++k) {
      keys[k] = p.clusters[k];
      std::sort(keys[k].begin(), keys[k].end());
      const auto known = fitted_.find(keys[k]);
      if (known != fitted_.end()) {
        p.boxes[k] = known->second;
      } else if (!p.points[k].empty()) {
        todo.push_back(k);
      }
    }
    // Each cluster carves against every other voxel seen: the clusters go to the cores.
    forEachRow(static_cast<int>(todo.size()), 0, [&](int row) {
      const std::size_t k = todo[static_cast<std::size_t>(row)];
      const auto self = static_cast<std::int32_t>(k);
      const CuboidObject seen_part = fitCuboid(p.points[k], params_.cuboid);
      p.boxes[k] = normalisedCuboid(extendHiddenSides(seen_part, lines_, OwnLines{&p.line_owner, self, self}, params_.hidden));
    });
    for (std::size_t k : todo) fitted_.emplace(std::move(keys[k]), p.boxes[k]);
    return p;
  }

  // Whether pieces a and b are one object: their boxes share merge_overlap of the smaller
  // one's volume (an object seen in parts: a table top and its front seen apart through
  // a sparse row of points), or their points nearly touch and the cuboid of both together
  // is solid as far as the rig can tell, hardly a ray passing through it (an object cut in
  // two by the shadow of something in front of it, as a table behind a loudspeaker
  // stand). Two pieces of furniture side by side are not: the rays to the floor between
  // them pass through their joint cuboid.
  bool sameObject(const Pieces& p, std::size_t a, std::size_t b) const {
    if (sharedFraction(p.boxes[a], p.boxes[b]) >= params_.merge_overlap) return true;
    if (p.points[a].empty() || p.points[b].empty() || !near(p.points[a], p.points[b], params_.join_gap_m)) {
      return false;
    }
    std::vector<Eigen::Vector3d> both = p.points[a];
    both.insert(both.end(), p.points[b].begin(), p.points[b].end());
    const CuboidObject joint = fitCuboid(both, params_.cuboid);
    const auto ia = static_cast<std::int32_t>(a), ib = static_cast<std::int32_t>(b);
    const std::size_t through = raysThroughBox(joint, lines_, OwnLines{&p.line_owner, ia, ib}, params_.hidden);
    // A few rays through it are strays (a mismatch reported beyond the surface it
    // missed): as many as a small fraction of the voxels seen of the two.
    const auto seen_voxels = static_cast<double>(p.clusters[a].size() + p.clusters[b].size());
    const double strays = params_.join_stray_fraction * seen_voxels;
    return static_cast<double>(through) < std::max(static_cast<double>(params_.hidden.free_rays), strays);
  }

 private:
  const PointCloud& cloud_;
  const VoxelGrid& grid_;
  const RoomFrame& frame_;
  const FurnitureParams& params_;
  std::vector<Eigen::Vector3d> room_centroid_;
  std::vector<std::uint32_t> seen_;  // the voxels inside the room, one line of sight each
  SightLines lines_;
  std::map<std::vector<std::uint32_t>, CuboidObject> fitted_;  // boxes fitted, by their sorted voxels
};

// The clusters with every pair the fitter takes for one object joined (transitively).
Clusters mergedClusters(const Pieces& pieces, const ClusterFitter& fitter) {
  const Clusters& clusters = pieces.clusters;
  // Every pair is judged on the cores first (a joint cuboid's fit and its rays cost
  // milliseconds, and the courtyard's clusters make hundreds of pairs), then joined in
  // order: the same groups as judging them one after the other.
  const std::size_t n = clusters.size();
  std::vector<std::uint8_t> same(n * n, 0);
  forEachRow(static_cast<int>(n), 0, [&](int row) {
    const auto a = static_cast<std::size_t>(row);
    for (std::size_t b = a + 1; b < n; ++b) same[a * n + b] = fitter.sameObject(pieces, a, b) ? 1 : 0;
  });
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      if (root(parent, a) == root(parent, b)) continue;
      if (same[a * n + b]) parent[root(parent, b)] = root(parent, a);
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

// An object whose bottom is in the upper 40 % of the room and whose top reaches within
// 0.6 m of the ceiling, standing against no wall.
bool hangsFromCeiling(const CuboidObject& object, const RoomFrame& frame, bool against_wall) {
  if (against_wall || !frame.has_ceiling) return false;
  const double bottom = object.center_m.z() - 0.5 * object.size_m.z();
  const double top = object.center_m.z() + 0.5 * object.size_m.z();
  return bottom >= 0.6 * frame.size.z() && top >= frame.size.z() - 0.6;
}

// An object in a room open to the sky that floats clear of the floor and of every wall:
// nothing is above it to hang from, and nothing of it reaches down or sideways to stand
// on, so it is no furniture but the stereo's scatter (the far walls' upper edges against
// the sky, ranged at little disparity, leave such clusters high in the air). Clear of
// the floor means its bottom above head height, so a table or counter whose legs went
// unseen stays; clear of a wall, every footprint corner more than the wall's margin (the
// layer of the wall's own points) and 10 cm from it, so a unit fixed to a wall stays.
bool floatsInOpenAir(const CuboidObject& object, const RoomFrame& frame) {
  constexpr double kFloorClearance = 2.0;  // [m]
  constexpr double kWallClearance = 0.1;   // [m] beyond the wall's margin
  if (frame.has_ceiling || object.center_m.z() - 0.5 * object.size_m.z() < kFloorClearance) return false;
  for (const auto& c : cuboidFootprint(object)) {
    const std::array<double, 4> to_wall = {c.x(), frame.size.x() - c.x(), c.y(), frame.size.y() - c.y()};
    for (std::size_t w = 0; w < to_wall.size(); ++w) {
      if (to_wall[w] <= frame.margin[w + 2] + kWallClearance) return false;
    }
  }
  return true;
}

// Per face (kRoomSurfaceNames order), the voxels in its window: each cluster's test asks
// for a few of them, and the courtyard has hundreds of clusters and 300 000 voxels.
using FaceWindows = std::array<std::vector<std::uint32_t>, 6>;
FaceWindows faceWindows(const std::vector<Eigen::Vector3d>& room_centroid, const RoomFrame& frame) {
  FaceWindows windows;
  for (std::uint32_t v = 0; v < room_centroid.size(); ++v) {
    const auto d = frame.faceDistances(room_centroid[v]);
    for (std::size_t f = 0; f < 6; ++f) {
      if (frame.usesFace(static_cast<int>(f)) && std::abs(d[f]) <= frame.margin[f]) windows[f].push_back(v);
    }
  }
  return windows;
}

// Whether a cluster is the tail of a face's range noise rather than something standing in
// front of the face. Where the stereo ranges a wall poorly (far, or seen steeply, where a
// vertical baseline gives little disparity) its points scatter far beyond the wall's
// window, and the scatter inside the room forms clusters clear of the faces; the ground of
// a large room seen at grazing angles scatters upwards the same way (the rendered
// courtyard's gravel 5-9 m from the rig left clusters 0.1-0.2 m high). Such a tail
// touches the face, is densest next to it and thins out into the room, and the face
// itself is seen behind it. Something against a wall or on the floor hides the face
// behind or under it, and its points gather at its front or top. So a cluster that
// touches face f (the floor or a wall) is a tail if, over the middle of its outline on
// the face, its points are densest in the layer next to the face's window and the window
// itself holds at least half that density.
bool faceNoiseTail(const std::vector<std::uint32_t>& cluster, const std::vector<Eigen::Vector3d>& room_centroid,
                   const std::vector<Voxel>& voxels, const FaceWindows& windows, const RoomFrame& frame,
                   double voxel_m) {
  constexpr double kOutline = 0.1;       // outline: the 10-90 % range of the cluster's voxels
  constexpr double kTouchVoxels = 2.0;   // a cluster within this many voxels of the window touches it
  constexpr double kFaceShare = 0.5;     // the window's density over the cluster's densest layer
  constexpr double kStandsOnFloorM = 0.2;   // a cluster whose lowest points are this near the floor ...
  constexpr double kStandingHeightM = 1.0;  // ... and that rises this high stands there
  constexpr double kFloorTailM = 0.3;       // the highest a tail of the floor's noise rises
  const auto quantile = [](std::vector<double> values, double q) {
    const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[static_cast<std::size_t>(k)];
  };
  for (int face : {0, 2, 3, 4, 5}) {
    const double margin = frame.margin[static_cast<std::size_t>(face)];
    // The two coordinates across the face: along the wall and up it, or the floor's x and y.
    const int first = face == 0 ? 0 : (face < 4 ? 1 : 0), second = face == 0 ? 1 : 2;
    std::vector<double> distance, across_first, across_second;
    for (std::uint32_t v : cluster) {
      const Eigen::Vector3d& p = room_centroid[v];
      distance.push_back(frame.faceDistances(p)[static_cast<std::size_t>(face)]);
      across_first.push_back(p[first]), across_second.push_back(p[second]);
    }
    if (quantile(distance, 0.02) > margin + kTouchVoxels * voxel_m) continue;
    // The ground's scatter rises a few decimetres at most (0.1-0.2 m from gravel 9 m from
    // the rendered courtyard's rig); a seat rises 0.4 m, and what rises that high is furniture.
    if (face == 0 && quantile(distance, 0.98) > kFloorTailM) continue;
    // Standing on the floor and rising a metre or more: shelving or a unit, whose wall
    // shows between its boards as a wall shows through its own noise.
    if (face != 0) {
      std::vector<double> height;
      for (std::uint32_t v : cluster) height.push_back(room_centroid[v].z());
      if (quantile(height, 0.02) <= kStandsOnFloorM &&
          quantile(height, 0.98) - quantile(height, 0.02) >= kStandingHeightM) {
        continue;
      }
    }
    const double a_lo = quantile(across_first, kOutline), a_hi = quantile(across_first, 1.0 - kOutline);
    const double b_lo = quantile(across_second, kOutline), b_hi = quantile(across_second, 1.0 - kOutline);
    const auto inOutline = [&](const Eigen::Vector3d& p) {
      return p[first] >= a_lo && p[first] <= a_hi && p[second] >= b_lo && p[second] <= b_hi;
    };
    // The cluster's points in layers of the window's thickness, from the window inwards.
    const double layer = std::max(2.0 * margin, 2.0 * voxel_m);
    std::vector<double> layers;
    for (std::size_t i = 0; i < cluster.size(); ++i) {
      const Eigen::Vector3d& p = room_centroid[cluster[i]];
      if (!inOutline(p) || distance[i] <= margin) continue;
      const auto k = static_cast<std::size_t>((distance[i] - margin) / layer);
      if (layers.size() <= k) layers.resize(k + 1, 0.0);
      layers[k] += voxels[cluster[i]].count;
    }
    if (layers.empty() || std::max_element(layers.begin(), layers.end()) != layers.begin()) continue;
    double window = 0.0;
    for (std::uint32_t v : windows[static_cast<std::size_t>(face)]) {
      if (inOutline(room_centroid[v])) window += voxels[v].count;
    }
    if (window / (2.0 * margin) >= kFaceShare * layers[0] / layer) return true;
  }
  return false;
}

}  // namespace

Furniture fitFurniture(const PointCloud& cloud, const VoxelGrid& grid, const RoomFrame& frame,
                       const FurnitureParams& params) {
  const auto& voxels = grid.voxels();
  ClusterFitter fitter(cloud, grid, frame, params);
  std::vector<bool> candidate(voxels.size(), false);
  for (std::size_t v = 0; v < voxels.size(); ++v) {
    candidate[v] = voxels[v].hint != VoxelHint::structure && frame.clearOfFaces(fitter.roomCentroids()[v]);
  }
  Clusters clusters =
      splitClustersAtNecks(grid, connectedVoxelClusters(grid, candidate, params.min_voxels, params.link_voxels),
                           params.link_voxels, params.split);
  // A split can leave a piece (a bridge's stub) below the size of an object; a face's
  // range noise is no object.
  const FaceWindows windows = faceWindows(fitter.roomCentroids(), frame);
  clusters.erase(std::remove_if(clusters.begin(), clusters.end(),
                                [&](const auto& c) {
                                  return c.size() < params.min_voxels ||
                                         faceNoiseTail(c, fitter.roomCentroids(), voxels, windows, frame, grid.size());
                                }),
                 clusters.end());
  Pieces pieces = fitter.fit(std::move(clusters));
  // Parts of one object seen in pieces are fitted again as one.
  Clusters merged = mergedClusters(pieces, fitter);
  if (merged.size() < pieces.clusters.size()) pieces = fitter.fit(std::move(merged));
  // A table is cut from the chairs around it; those pieces are final. The rest, pieces
  // side by side or stacked (a base run, its fridge, the wall units above), are cut
  // apart, and what that cut separated wrongly is joined again.
  TableSplitParams table = params.table;
  table.min_voxels = params.min_voxels;
  TableSplit tables = splitTablesFromChairs(pieces.clusters, fitter.roomCentroids(), grid.size(), table);
  std::vector<CuboidObject> rest_boxes;
  for (std::size_t k : tables.rest_index) rest_boxes.push_back(pieces.boxes[k]);
  ProfileSplitParams profile = params.profile;
  profile.min_voxels = params.min_voxels;
  Clusters cut = splitClustersAtStepsAndStacks(tables.rest, rest_boxes, fitter.roomCentroids(), grid.size(), profile);
  const bool was_cut = cut.size() > tables.rest.size();
  if (was_cut) cut = mergedClusters(fitter.fit(std::move(cut)), fitter);
  if (was_cut || !tables.tables_and_chairs.empty()) {
    cut.insert(cut.end(), tables.tables_and_chairs.begin(), tables.tables_and_chairs.end());
    pieces = fitter.fit(std::move(cut));
  }

  Furniture furniture;
  std::vector<std::int32_t> cluster_object(pieces.clusters.size(), -1);
  for (std::size_t k = 0; k < pieces.clusters.size(); ++k) {
    CuboidObject object = pieces.boxes[k];
    if (object.size_m.maxCoeff() < params.min_extent_m || (object.size_m.array() <= 0.0).any()) continue;
    const bool on_floor = object.center_m.z() - 0.5 * object.size_m.z() <= 1e-9;
    const bool against_wall = againstWall(object, frame.size);
    // Lights and ducts hang from the ceiling, clear of the walls: not furniture, and too
    // small and high to shape the room's sound. Without a ceiling, nothing hangs.
    if (hangsFromCeiling(object, frame, against_wall) || floatsInOpenAir(object, frame)) continue;
    object.label = furnitureLabel(object, on_floor, against_wall);
    object.material = "";  // placeholder: the material step names it
    object.confidence = objectConfidence(pieces.clusters[k].size(), object.label);
    cluster_object[k] = static_cast<std::int32_t>(furniture.objects.size());
    furniture.objects.push_back(object);
  }
  furniture.voxel_object.assign(voxels.size(), -1);
  for (std::size_t v = 0; v < voxels.size(); ++v) {
    const std::int32_t k = pieces.voxel_cluster[v];
    if (k >= 0) furniture.voxel_object[v] = cluster_object[static_cast<std::size_t>(k)];
  }
  return furniture;
}

}  // namespace room_reverb::core::layout
