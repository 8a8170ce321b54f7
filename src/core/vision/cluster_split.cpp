#include "cluster_split.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <deque>

#include "object_clusters.h"

namespace room_reverb::core::layout {

namespace {

using Cluster = std::vector<std::uint32_t>;

// A cluster's footprint: one raster cell per voxel column, with a border wide enough
// that the morphology never reaches the raster's edge.
struct Footprint {
  cv::Mat occupied;                                  // CV_8UC1, 255 where a voxel of the cluster stands
  Eigen::Vector2i origin = Eigen::Vector2i::Zero();  // voxel cell at raster (0, 0)

  cv::Point at(const Voxel& voxel) const { return {voxel.cell.x() - origin.x(), voxel.cell.y() - origin.y()}; }
};

Footprint footprintOf(const VoxelGrid& grid, const Cluster& cluster, int border) {
  const auto& voxels = grid.voxels();
  Eigen::Vector2i lo = voxels[cluster.front()].cell.head<2>(), hi = lo;
  for (std::uint32_t v : cluster) {
    lo = lo.cwiseMin(voxels[v].cell.head<2>());
    hi = hi.cwiseMax(voxels[v].cell.head<2>());
  }
  Footprint f;
  f.origin = lo - Eigen::Vector2i::Constant(border);
  const Eigen::Vector2i extent = hi - lo + Eigen::Vector2i::Constant(2 * border + 1);
  f.occupied = cv::Mat::zeros(extent.y(), extent.x(), CV_8UC1);
  for (std::uint32_t v : cluster) f.occupied.at<std::uint8_t>(f.at(voxels[v])) = 255;
  return f;
}

// Labels (1..n) of the footprint's cores, 0 elsewhere; n is returned in `cores`.
cv::Mat coreLabels(const cv::Mat& closed, int neck_cells, int min_core_cells, int& cores) {
  cv::Mat eroded;
  const int side = 2 * neck_cells + 1;
  cv::erode(closed, eroded, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)));
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(eroded, labels, stats, centroids, 8, CV_32S);
  // Renumber the cores large enough to count; the rest go back to 0.
  std::vector<int> renumber(static_cast<std::size_t>(n), 0);
  cores = 0;
  for (int k = 1; k < n; ++k) {
    if (stats.at<int>(k, cv::CC_STAT_AREA) >= min_core_cells) renumber[static_cast<std::size_t>(k)] = ++cores;
  }
  for (int r = 0; r < labels.rows; ++r) {
    for (int c = 0; c < labels.cols; ++c) {
      int& label = labels.at<int>(r, c);
      label = renumber[static_cast<std::size_t>(label)];
    }
  }
  return labels;
}

// Grows the core labels over the closed footprint, breadth first (8 neighbours), at most
// `reach` cells: each cell within reach takes the label of the core nearest to it along
// the footprint; the rest stay 0.
void growLabels(cv::Mat& labels, const cv::Mat& closed, int reach) {
  cv::Mat distance(labels.size(), CV_32S, cv::Scalar(-1));
  std::deque<cv::Point> queue;
  for (int r = 0; r < labels.rows; ++r) {
    for (int c = 0; c < labels.cols; ++c) {
      if (labels.at<int>(r, c) > 0) queue.emplace_back(c, r), distance.at<int>(r, c) = 0;
    }
  }
  while (!queue.empty()) {
    const cv::Point p = queue.front();
    queue.pop_front();
    if (distance.at<int>(p) >= reach) continue;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const cv::Point q(p.x + dx, p.y + dy);
        if (q.x < 0 || q.y < 0 || q.x >= labels.cols || q.y >= labels.rows) continue;
        if (closed.at<std::uint8_t>(q) == 0 || distance.at<int>(q) >= 0) continue;
        labels.at<int>(q) = labels.at<int>(p);
        distance.at<int>(q) = distance.at<int>(p) + 1;
        queue.push_back(q);
      }
    }
  }
}

// The connected parts of a set of voxels, linked as the clusters were.
std::vector<Cluster> connectedParts(const VoxelGrid& grid, const Cluster& voxels, int link_voxels) {
  std::vector<bool> member(grid.voxels().size(), false);
  for (std::uint32_t v : voxels) member[v] = true;
  return connectedVoxelClusters(grid, member, 1, link_voxels);
}

int cellsOf(double metres, double voxel) { return std::max(1, static_cast<int>(std::lround(metres / voxel))); }

}  // namespace

std::vector<Cluster> splitClustersAtNecks(const VoxelGrid& grid, const std::vector<Cluster>& clusters,
                                          int link_voxels, const ClusterSplitParams& params) {
  const int neck = cellsOf(params.neck_m, grid.size());
  const int reach = cellsOf(params.reach_m, grid.size());
  const int min_core = std::max(1, static_cast<int>(std::ceil(params.min_core_area_m2 / (grid.size() * grid.size()))));
  const cv::Mat square3 = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  std::vector<Cluster> out;
  for (const Cluster& cluster : clusters) {
    if (cluster.empty()) continue;
    const Footprint footprint = footprintOf(grid, cluster, neck + 2);
    // Closed first: a top seen at a slant leaves gaps of a voxel between its rows of
    // points, which must not shred it.
    cv::Mat closed;
    cv::morphologyEx(footprint.occupied, closed, cv::MORPH_CLOSE, square3);
    int cores = 0;
    cv::Mat labels = coreLabels(closed, neck, min_core, cores);
    if (cores == 0) {
      out.push_back(cluster);
      continue;
    }
    growLabels(labels, closed, neck + reach);
    // One part per core, and one (split below) for the columns out of every core's reach.
    std::vector<Cluster> parts(static_cast<std::size_t>(cores) + 1);
    for (std::uint32_t v : cluster) {
      const int label = labels.at<int>(footprint.at(grid.voxels()[v]));
      parts[static_cast<std::size_t>(label > 0 ? label - 1 : cores)].push_back(v);
    }
    for (int k = 0; k < cores; ++k) out.push_back(std::move(parts[static_cast<std::size_t>(k)]));
    for (Cluster& piece : connectedParts(grid, parts.back(), link_voxels)) out.push_back(std::move(piece));
  }
  return out;
}

}  // namespace room_reverb::core::layout
