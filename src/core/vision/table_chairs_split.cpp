#include "table_chairs_split.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace room_reverb::core::layout {

namespace {

using Cluster = std::vector<std::uint32_t>;

// Voxels (by position) linked through neighbours at most `reach` apart along each axis,
// largest group first.
std::vector<Cluster> linkedGroups(const Cluster& voxels, const std::vector<Eigen::Vector3d>& at, double reach) {
  Cluster order = voxels;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return at[a].x() < at[b].x(); });
  std::vector<std::size_t> parent(order.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto root = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::size_t i = 0; i < order.size(); ++i) {
    for (std::size_t j = i + 1; j < order.size() && at[order[j]].x() - at[order[i]].x() <= reach; ++j) {
      if ((at[order[j]] - at[order[i]]).cwiseAbs().maxCoeff() <= reach) parent[root(j)] = root(i);
    }
  }
  std::vector<Cluster> groups(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) groups[root(i)].push_back(order[i]);
  groups.erase(std::remove_if(groups.begin(), groups.end(), [](const Cluster& g) { return g.empty(); }), groups.end());
  std::sort(groups.begin(), groups.end(), [](const Cluster& a, const Cluster& b) { return a.size() > b.size(); });
  return groups;
}

// The cluster as a table and its chairs (see the header), or whole.
std::vector<Cluster> cutAtTableTop(const Cluster& cluster, const std::vector<Eigen::Vector3d>& at, double cell_m,
                                   const TableSplitParams& params) {
  // The layer: a cell-high band, counted with its two neighbours.
  std::map<int, std::size_t> band;
  for (std::uint32_t v : cluster) ++band[static_cast<int>(std::floor(at[v].z() / cell_m))];
  int top_band = 0;
  std::size_t most = 0;
  for (const auto& [b, count] : band) {
    const double z = (b + 0.5) * cell_m;
    if (z < params.low_m || z > params.high_m) continue;
    const std::size_t layer = count + (band.count(b - 1) ? band.at(b - 1) : 0) + (band.count(b + 1) ? band.at(b + 1) : 0);
    if (layer > most) most = layer, top_band = b;
  }
  if (most < params.min_voxels) return {cluster};
  const double top_lo = (top_band - 1) * cell_m, top_hi = (top_band + 2) * cell_m;
  // The top's plan: the largest patch of the layer's voxel columns linked across gaps of
  // up to a cell (a top seen at a slant shows as rows of points), grown by a cell; the
  // backs of chairs cross the layer too, a hand's width or more away.
  std::set<std::pair<int, int>> layer;
  for (std::uint32_t v : cluster) {
    if (at[v].z() < top_lo || at[v].z() >= top_hi) continue;
    layer.insert({static_cast<int>(std::floor(at[v].x() / cell_m)), static_cast<int>(std::floor(at[v].y() / cell_m))});
  }
  std::set<std::pair<int, int>> top, seen;
  for (const auto& start : layer) {
    if (seen.count(start)) continue;
    std::set<std::pair<int, int>> patch = {start};
    std::vector<std::pair<int, int>> stack = {start};
    seen.insert(start);
    while (!stack.empty()) {
      const auto [x, y] = stack.back();
      stack.pop_back();
      for (int dx = -2; dx <= 2; ++dx) {
        for (int dy = -2; dy <= 2; ++dy) {
          const std::pair<int, int> next(x + dx, y + dy);
          if (layer.count(next) && !seen.count(next)) seen.insert(next), patch.insert(next), stack.push_back(next);
        }
      }
    }
    if (patch.size() > top.size()) top = std::move(patch);
  }
  std::set<std::pair<int, int>> plan;
  for (const auto& [x, y] : top) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) plan.insert({x + dx, y + dy});
    }
  }
  Cluster table, outside;
  std::size_t under = 0, above = 0;
  for (std::uint32_t v : cluster) {
    const std::pair<int, int> cell(static_cast<int>(std::floor(at[v].x() / cell_m)), static_cast<int>(std::floor(at[v].y() / cell_m)));
    if (plan.count(cell)) {
      table.push_back(v);
      under += at[v].z() < top_lo - params.clearance_m ? 1 : 0;
      above += at[v].z() >= top_hi + params.clearance_m ? 1 : 0;
    } else {
      outside.push_back(v);
    }
  }
  // A top with a body under it (a cabinet, a sofa's seat, a worktop) is no table, nor one
  // that something tall rises from or stands flush with (a wardrobe's front beside it).
  const double little = params.max_under_fraction * static_cast<double>(most);
  if (static_cast<double>(under) > little || static_cast<double>(above) > little) return {cluster};
  std::vector<Cluster> pieces;
  for (Cluster& group : linkedGroups(outside, at, 1.5 * cell_m)) {
    if (group.size() >= params.min_voxels) {
      // Something larger than a chair beside the top (wall units over a worktop, a fridge)
      // says this is no table with chairs.
      Eigen::AlignedBox3d box;
      for (std::uint32_t v : group) box.extend(at[v]);
      if (box.sizes().head<2>().maxCoeff() > params.max_chair_extent_m || box.max().z() > params.max_chair_height_m) {
        return {cluster};
      }
      pieces.push_back(std::move(group));
    } else {
      table.insert(table.end(), group.begin(), group.end());
    }
  }
  if (pieces.empty()) return {cluster};
  // A chair pushed in has its seat under the top's edge: what stands under the top
  // (lower than the clearance below it, down to seat_low_m) within reach of a chair's plan
  // is that chair's. The table keeps what is lower: its legs' feet, which the rays
  // passing under the top do not let the hidden-side carving put back.
  std::vector<Eigen::AlignedBox2d> chair_plans;
  for (const Cluster& chair : pieces) {
    Eigen::AlignedBox2d box;
    for (std::uint32_t v : chair) box.extend(at[v].head<2>());
    chair_plans.push_back(box);
  }
  Cluster kept;
  for (std::uint32_t v : table) {
    std::size_t nearest = pieces.size();
    double best = params.pushed_in_reach_m;
    if (at[v].z() < top_lo - params.clearance_m && at[v].z() >= params.seat_low_m) {
      for (std::size_t c = 0; c < chair_plans.size(); ++c) {
        const double d = chair_plans[c].exteriorDistance(Eigen::Vector2d(at[v].head<2>()));
        if (d <= best) best = d, nearest = c;
      }
    }
    (nearest < pieces.size() ? pieces[nearest] : kept).push_back(v);
  }
  pieces.insert(pieces.begin(), std::move(kept));
  return pieces;
}

}  // namespace

TableSplit splitTablesFromChairs(const std::vector<std::vector<std::uint32_t>>& clusters,
                                 const std::vector<Eigen::Vector3d>& room_centroid, double cell_m,
                                 const TableSplitParams& params) {
  TableSplit split;
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    std::vector<Cluster> pieces = cutAtTableTop(clusters[k], room_centroid, cell_m, params);
    if (pieces.size() > 1) {
      for (Cluster& piece : pieces) split.tables_and_chairs.push_back(std::move(piece));
    } else {
      split.rest.push_back(std::move(pieces.front()));
      split.rest_index.push_back(k);
    }
  }
  return split;
}

}  // namespace room_reverb::core::layout
