#include "room_reverb/vision/surface_relief.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "room_reverb/acoustics/relief_scattering.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

// A face of the box [0, size]: its normal axis, which side, and its two in-plane axes.
struct BoxFace {
  int axis;     // 0 x, 1 y, 2 z
  bool at_max;  // the face at size[axis] (its height is size - coordinate)
  int u, v;     // in-plane axes
};

// kRoomSurfaceNames order: floor, ceiling, wall_x_min, wall_x_max, wall_y_min, wall_y_max.
constexpr std::array<BoxFace, 6> kFaces = {{{2, false, 0, 1}, {2, true, 0, 1}, {0, false, 1, 2},
                                            {0, true, 1, 2},  {1, false, 0, 2}, {1, true, 0, 2}}};

void checkOptions(const SurfaceReliefOptions& o) {
  const auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string("surface relief: ") + name + " must be positive");
  };
  positive(o.cell_m, "cell_m");
  positive(o.max_height_m, "max_height_m");
  positive(o.speed_of_sound_m_s, "speed_of_sound_m_s");
  if (!(o.min_seen_m2 >= 0.0) || !std::isfinite(o.min_seen_m2)) throw InputError("surface relief: min_seen_m2 must be >= 0");
  if (o.min_points_per_cell < 1) throw InputError("surface relief: min_points_per_cell must be at least 1");
}

// The heights of one face's points, by cell.
class CellHeights {
 public:
  // `margin`: a point this close to the face's reference height is on it (its noise).
  void add(std::int64_t cell, double height, double margin = 0.0) {
    samples_.push_back({cell, static_cast<float>(height), static_cast<float>(margin)});
  }

  // Each seen cell's median height (cells with at least min_points points), from the
  // reference: 0 (the fitted plane of a room face), or for an object's face the median of
  // its points (a box fitted a few centimetres proud of what it holds is a plane moved,
  // not a relief); points within their margin of the reference are on it.
  std::vector<double> cellHeights(const SurfaceReliefOptions& options, bool from_median) {
    if (samples_.empty()) return {};
    float reference = 0.0f;
    if (from_median) {
      std::vector<float> all;
      all.reserve(samples_.size());
      for (const Sample& sample : samples_) all.push_back(sample.height);
      auto middle = all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2);
      std::nth_element(all.begin(), middle, all.end());
      reference = *middle;
    }
    for (Sample& sample : samples_) {
      sample.height -= reference;
      if (std::abs(sample.height) < sample.margin) sample.height = 0.0f;
    }
    std::sort(samples_.begin(), samples_.end(), [](const Sample& a, const Sample& b) { return a.cell < b.cell; });
    std::vector<double> heights;
    std::vector<float> cell;
    for (std::size_t begin = 0; begin < samples_.size();) {
      std::size_t end = begin;
      cell.clear();
      while (end < samples_.size() && samples_[end].cell == samples_[begin].cell) cell.push_back(samples_[end++].height);
      begin = end;
      if (cell.size() < options.min_points_per_cell) continue;
      auto middle = cell.begin() + static_cast<std::ptrdiff_t>(cell.size() / 2);
      std::nth_element(cell.begin(), middle, cell.end());
      heights.push_back(*middle);
    }
    return heights;
  }

 private:
  struct Sample {
    std::int64_t cell;
    float height, margin;
  };
  std::vector<Sample> samples_;
};

// The relief of a surface seen as one or more faces (a room face; an object's box), each
// with its seen cells' heights: its scattering is the seen-area-weighted mean of the
// faces' own (a face's specular reflection is its own; two faces of a box do not
// interfere in one specular direction).
ReliefEstimate reliefOf(const std::vector<std::vector<double>>& faces, const SurfaceReliefOptions& options) {
  ReliefEstimate relief;
  std::size_t cells = 0, off = 0;
  double sum2 = 0.0;
  for (const std::vector<double>& heights : faces) {
    cells += heights.size();
    for (double h : heights) {
      sum2 += h * h;
      off += h != 0.0 ? 1 : 0;
    }
  }
  relief.seen_m2 = static_cast<double>(cells) * options.cell_m * options.cell_m;
  if (cells == 0 || relief.seen_m2 < options.min_seen_m2) return relief;
  relief.estimated = true;
  relief.rms_height_m = std::sqrt(sum2 / static_cast<double>(cells));
  relief.relief_share = static_cast<double>(off) / static_cast<double>(cells);
  for (const std::vector<double>& heights : faces) {
    if (heights.empty()) continue;
    const OctaveBandValues s = reliefScattering(heights, options.speed_of_sound_m_s);
    const double weight = static_cast<double>(heights.size()) / static_cast<double>(cells);
    for (int b = 0; b < kOctaveBandCount; ++b) relief.scattering[b] += weight * s[b];
  }
  return relief;
}

// The face of a box (half extents `half`, its own frame) through which a ray from `eye`
// enters it on its way to `point`: its axis and outward sign. Where the ray does not
// enter the box before the point (the eye inside it, a point outside it), the face
// nearest the point.
std::pair<int, double> faceSeenThrough(const Eigen::Vector3d& eye, const Eigen::Vector3d& point, const Eigen::Vector3d& half) {
  const Eigen::Vector3d d = point - eye;
  double enter = -std::numeric_limits<double>::infinity(), leave = std::numeric_limits<double>::infinity();
  int axis = -1;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (std::abs(eye[a]) > half[a]) enter = leave = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    const double t0 = (-std::copysign(half[a], d[a]) - eye[a]) / d[a], t1 = (std::copysign(half[a], d[a]) - eye[a]) / d[a];
    if (t0 > enter) enter = t0, axis = a;
    leave = std::min(leave, t1);
  }
  if (axis >= 0 && enter >= 0.0 && enter <= 1.0 && enter <= leave) return {axis, d[axis] > 0.0 ? -1.0 : 1.0};
  const Eigen::Vector3d inside = half - point.cwiseAbs();
  int nearest = 0;
  inside.minCoeff(&nearest);
  return {nearest, point[nearest] >= 0.0 ? 1.0 : -1.0};
}

std::int64_t cellIndex(double coordinate, double cell_m) { return static_cast<std::int64_t>(std::floor(coordinate / cell_m)); }

}  // namespace

SurfaceReliefs estimateSurfaceRelief(const PointCloud& cloud, const RoomLayout& layout, const Eigen::Isometry3d& room_from_cloud,
                                     const RoomLayoutOptions& layout_options, const SurfaceReliefOptions& options) {
  checkOptions(options);
  const std::vector<CuboidObject>& objects = layout.model.objects;
  SurfaceReliefs result;
  result.objects.resize(objects.size());
  if (!options.enabled) return result;
  if (layout.point_surface.size() != cloud.points.size() || layout.point_object.size() != cloud.points.size()) {
    throw InputError("surface relief: the layout's point labels do not match the cloud (fit it with assign_points)");
  }
  const Eigen::Vector3d size = layout.model.size_m;
  const Eigen::Vector3d rig = room_from_cloud.translation();
  std::array<bool, 6> used{};
  for (std::size_t f = 0; f < 6; ++f) used[f] = !layout.face_evidence[f].open && (f != 1 || layout.model.has_ceiling);
  // A cell's key: its row times this, plus its column (rows and columns below 2^20).
  constexpr std::int64_t kColumns = 1 << 20;
  std::array<CellHeights, 6> faces;
  std::vector<std::array<CellHeights, 6>> cuboids(objects.size());
  std::vector<Eigen::Vector3d> eyes;  // the rig in each object's own frame
  for (const CuboidObject& box : objects) eyes.push_back(toCuboidFrame(box, rig));

  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const Eigen::Vector3d p = room_from_cloud * cloud.points[i].p.cast<double>();
    const int object = layout.point_object[i];
    if (object >= 0 && static_cast<std::size_t>(object) < objects.size()) {
      // From the face of the object's box that the rig sees the point through, and how far
      // outside it the point lies (negative inside), with the layout's face margin at the
      // point's range.
      const CuboidObject& box = objects[static_cast<std::size_t>(object)];
      const Eigen::Vector3d local = toCuboidFrame(box, p);
      const auto [axis, outward] = faceSeenThrough(eyes[static_cast<std::size_t>(object)], local, 0.5 * box.size_m);
      const double height = outward * local[axis] - 0.5 * box.size_m[axis];
      const double range = cloud.points[i].p.cast<double>().norm();
      const double margin = std::max(layout_options.min_face_margin_m,
                                     layout_options.noise_sigmas * layout_options.range_noise_fraction * range);
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const std::size_t face = static_cast<std::size_t>(2 * axis + (outward > 0.0 ? 1 : 0));
      cuboids[static_cast<std::size_t>(object)][face].add(
          cellIndex(local[u] + 0.5 * box.size_m[u], options.cell_m) * kColumns +
              cellIndex(local[v] + 0.5 * box.size_m[v], options.cell_m),
          height, margin);
      continue;
    }
    // On a face (height 0), or off every face and object: then the nearest face whose
    // extent holds the point's footprint, up to max_height_m (a point beyond two faces,
    // past the box's edge, is a stray).
    int best = -1;
    double best_height = 0.0;
    const int on_face = layout.point_surface[i];
    if (on_face >= 0 && on_face < 6) {
      best = on_face;
    } else {
      for (int f = 0; f < 6; ++f) {
        const BoxFace& face = kFaces[static_cast<std::size_t>(f)];
        if (!used[static_cast<std::size_t>(f)] || p[face.u] < 0.0 || p[face.u] > size[face.u] || p[face.v] < 0.0 ||
            p[face.v] > size[face.v]) {
          continue;
        }
        const double h = face.at_max ? size[face.axis] - p[face.axis] : p[face.axis];
        if (std::abs(h) <= options.max_height_m && (best < 0 || std::abs(h) < std::abs(best_height))) best = f, best_height = h;
      }
    }
    if (best < 0 || !used[static_cast<std::size_t>(best)]) continue;
    const BoxFace& face = kFaces[static_cast<std::size_t>(best)];
    faces[static_cast<std::size_t>(best)].add(
        cellIndex(std::clamp(p[face.u], 0.0, size[face.u]), options.cell_m) * kColumns +
            cellIndex(std::clamp(p[face.v], 0.0, size[face.v]), options.cell_m),
        best_height);
  }
  for (std::size_t f = 0; f < 6; ++f) {
    if (used[f]) result.faces[f] = reliefOf({faces[f].cellHeights(options, false)}, options);
  }
  for (std::size_t k = 0; k < objects.size(); ++k) {
    std::vector<std::vector<double>> box_faces;
    for (CellHeights& face : cuboids[k]) box_faces.push_back(face.cellHeights(options, true));
    result.objects[k] = reliefOf(box_faces, options);
  }
  return result;
}

void applySurfaceRelief(RoomLayout& layout, const SurfaceReliefs& relief) {
  layout.face_relief = relief.faces;
  layout.object_relief = relief.objects;
  for (std::size_t f = 0; f < 6; ++f) {
    const auto it = layout.model.surfaces.find(kRoomSurfaceNames[f]);
    if (relief.faces[f].estimated && it != layout.model.surfaces.end()) it->second.relief_scattering = relief.faces[f].scattering;
  }
  for (std::size_t k = 0; k < relief.objects.size() && k < layout.model.objects.size(); ++k) {
    if (relief.objects[k].estimated) layout.model.objects[k].relief_scattering = relief.objects[k].scattering;
  }
}

}  // namespace room_reverb::core
