#include "cluster_profile_split.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace room_reverb::core::layout {

namespace {

using Cluster = std::vector<std::uint32_t>;

// The cluster's voxels by column along `axis` (unit, horizontal), cell_m wide.
std::vector<Cluster> columnsAlong(const Cluster& cluster, const std::vector<Eigen::Vector3d>& at,
                                  const Eigen::Vector2d& axis, double cell_m) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::uint32_t v : cluster) {
    const double u = axis.dot(at[v].head<2>());
    lo = std::min(lo, u), hi = std::max(hi, u);
  }
  std::vector<Cluster> columns(static_cast<std::size_t>((hi - lo) / cell_m) + 1);
  for (std::uint32_t v : cluster) {
    columns[static_cast<std::size_t>((axis.dot(at[v].head<2>()) - lo) / cell_m)].push_back(v);
  }
  return columns;
}

// A column's top: its highest voxel with another of the column at most two cells below
// (a stray voxel above the piece is not its top). NaN for an empty column.
double columnTop(const Cluster& column, const std::vector<Eigen::Vector3d>& at, double cell_m) {
  std::vector<double> z;
  for (std::uint32_t v : column) z.push_back(at[v].z());
  if (z.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(z.begin(), z.end(), std::greater<>());
  for (std::size_t i = 0; i + 1 < z.size(); ++i) {
    if (z[i] - z[i + 1] <= 2.0 * cell_m) return z[i];
  }
  return z.back();
}

double median(std::vector<double> values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// The cluster cut where its top steps (see the header). The top of each column is taken
// as the highest within envelope_columns either side: a top seen at a slant leaves rows of
// points with gaps between (shelving's top board far from the rig), and the tops of the
// books below must not read as steps. Consecutive columns whose tops stay within step_m of
// their run's median are one piece; a change must hold for two columns. Each cut then
// moves to where the columns' own tops cross halfway between the two levels (the envelope
// carries the higher level envelope_columns into the lower piece). Runs of fewer than
// min_voxels voxels join the neighbour whose top is nearest.
std::vector<Cluster> cutAtSteps(const Cluster& cluster, const std::vector<Eigen::Vector3d>& at,
                                const Eigen::Vector2d& axis, double cell_m, const ProfileSplitParams& params) {
  constexpr int kEnvelopeColumns = 3;
  const std::vector<Cluster> columns = columnsAlong(cluster, at, axis, cell_m);
  const int n = static_cast<int>(columns.size());
  std::vector<double> raw(columns.size()), top(columns.size());
  for (std::size_t i = 0; i < columns.size(); ++i) raw[i] = columnTop(columns[i], at, cell_m);
  for (int i = 0; i < n; ++i) {
    top[static_cast<std::size_t>(i)] = std::numeric_limits<double>::quiet_NaN();
    for (int j = std::max(0, i - kEnvelopeColumns); j <= std::min(n - 1, i + kEnvelopeColumns); ++j) {
      const double t = raw[static_cast<std::size_t>(j)];
      if (!std::isnan(t) && !(t <= top[static_cast<std::size_t>(i)])) top[static_cast<std::size_t>(i)] = t;
    }
  }
  // Runs as [first column, end column) with their tops; their voxels are counted once
  // the cuts have moved.
  struct Run {
    int first = 0, end = 0;
    std::vector<double> tops;
    std::size_t voxels = 0;
  };
  std::vector<Run> runs(1);
  for (int i = 0; i < n; ++i) {
    const double t = top[static_cast<std::size_t>(i)];
    if (!std::isnan(t) && !runs.back().tops.empty()) {
      const double ref = median(runs.back().tops);
      const auto differs = [&](double x) { return !std::isnan(x) && std::abs(x - ref) > params.step_m; };
      int next = i + 1;
      while (next < n && std::isnan(top[static_cast<std::size_t>(next)])) ++next;
      const bool holds = next == n || (differs(top[static_cast<std::size_t>(next)]) &&
                                       (top[static_cast<std::size_t>(next)] > ref) == (t > ref));
      if (differs(t) && holds) {
        runs.back().end = i;
        runs.emplace_back();
        runs.back().first = i;
      }
    }
    if (!std::isnan(t)) runs.back().tops.push_back(t);
  }
  runs.back().end = n;
  for (std::size_t r = 1; r < runs.size(); ++r) {
    const double lower_level = median(runs[r - 1].tops), upper_level = median(runs[r].tops);
    const double mid = 0.5 * (lower_level + upper_level);
    const bool rising = upper_level > lower_level;
    // The first column, scanning from kEnvelopeColumns before the cut, on the new run's side.
    int cut = runs[r].first;
    for (int i = std::max(runs[r - 1].first + 1, runs[r].first - kEnvelopeColumns);
         i <= std::min(runs[r].end - 1, runs[r].first + kEnvelopeColumns); ++i) {
      const double t = raw[static_cast<std::size_t>(i)];
      if (!std::isnan(t) && (t > mid) == rising) {
        cut = i;
        break;
      }
    }
    runs[r - 1].end = runs[r].first = cut;
  }
  for (Run& run : runs) {
    run.voxels = 0;
    for (int i = run.first; i < run.end; ++i) run.voxels += columns[static_cast<std::size_t>(i)].size();
  }
  // Small runs join a neighbour, the one with the nearer top.
  for (bool joined = true; joined && runs.size() > 1;) {
    joined = false;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      if (runs[r].voxels >= params.min_voxels) continue;
      const double t = runs[r].tops.empty() ? 0.0 : median(runs[r].tops);
      const auto gap = [&](std::size_t k) { return runs[k].tops.empty() ? 0.0 : std::abs(median(runs[k].tops) - t); };
      const std::size_t into = r == 0 ? 1 : r + 1 == runs.size() ? r - 1 : (gap(r - 1) <= gap(r + 1) ? r - 1 : r + 1);
      runs[into].first = std::min(runs[into].first, runs[r].first);
      runs[into].end = std::max(runs[into].end, runs[r].end);
      runs[into].voxels += runs[r].voxels;
      runs[into].tops.insert(runs[into].tops.end(), runs[r].tops.begin(), runs[r].tops.end());
      runs.erase(runs.begin() + static_cast<std::ptrdiff_t>(r));
      joined = true;
      break;
    }
  }
  std::vector<Cluster> pieces;
  for (const Run& run : runs) {
    Cluster piece;
    for (int i = run.first; i < run.end; ++i) {
      piece.insert(piece.end(), columns[static_cast<std::size_t>(i)].begin(), columns[static_cast<std::size_t>(i)].end());
    }
    if (!piece.empty()) pieces.push_back(std::move(piece));
  }
  return pieces;
}

// The piece cut at its widest empty horizontal band, if that is at least stack_gap_m
// high and both sides hold min_voxels.
std::vector<Cluster> cutAtStack(const Cluster& piece, const std::vector<Eigen::Vector3d>& at,
                                const ProfileSplitParams& params) {
  std::vector<double> z;
  for (std::uint32_t v : piece) z.push_back(at[v].z());
  std::sort(z.begin(), z.end());
  double widest = 0.0, cut = 0.0;
  std::size_t below = 0;
  for (std::size_t i = 0; i + 1 < z.size(); ++i) {
    if (z[i + 1] - z[i] > widest) widest = z[i + 1] - z[i], cut = 0.5 * (z[i] + z[i + 1]), below = i + 1;
  }
  if (widest < params.stack_gap_m || below < params.min_voxels || z.size() - below < params.min_voxels) return {piece};
  Cluster lower, upper;
  for (std::uint32_t v : piece) (at[v].z() < cut ? lower : upper).push_back(v);
  return {lower, upper};
}

}  // namespace

std::vector<std::vector<std::uint32_t>> splitClustersAtStepsAndStacks(
    const std::vector<std::vector<std::uint32_t>>& clusters, const std::vector<CuboidObject>& boxes,
    const std::vector<Eigen::Vector3d>& room_centroid, double cell_m, const ProfileSplitParams& params) {
  std::vector<Cluster> out;
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    if (clusters[k].empty()) continue;
    // The longer horizontal axis of the cluster's cuboid.
    const double yaw = boxes[k].yaw_rad + (boxes[k].size_m.y() > boxes[k].size_m.x() ? 0.5 * M_PI : 0.0);
    const Eigen::Vector2d axis(std::cos(yaw), std::sin(yaw));
    const std::vector<Cluster> pieces =
        params.step_m > 0.0 ? cutAtSteps(clusters[k], room_centroid, axis, cell_m, params) : std::vector<Cluster>{clusters[k]};
    for (const Cluster& piece : pieces) {
      if (params.stack_gap_m <= 0.0) {
        out.push_back(piece);
        continue;
      }
      for (Cluster& part : cutAtStack(piece, room_centroid, params)) out.push_back(std::move(part));
    }
  }
  return out;
}

}  // namespace room_reverb::core::layout
