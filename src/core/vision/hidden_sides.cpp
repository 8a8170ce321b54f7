#include "hidden_sides.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

#include "room_reverb/vision/oriented_box_iou.h"

namespace room_reverb::core::layout {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// Where the segment a -> b first enters the axis-aligned box [lo, hi]: its parameter in
// [0, 1], or infinity if it misses (slab method).
double segmentEntry(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& lo,
                    const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = b - a;
  double enter = 0.0, leave = 1.0;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (a[k] < lo[k] || a[k] > hi[k]) return kInf;
      continue;
    }
    double t0 = (lo[k] - a[k]) / d[k], t1 = (hi[k] - a[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return kInf;
  }
  return enter;
}

// The end of the stretch of the ray rig -> q that is known empty: short of q by the
// point's noise; false if nothing of it is.
bool trustedEnd(const Eigen::Vector3d& rig, const Eigen::Vector3d& q, const HiddenSideParams& params,
                Eigen::Vector3d& end) {
  const Eigen::Vector3d ray = q - rig;
  const double length = ray.norm();
  const double trusted = length * (1.0 - params.noise_sigmas * params.noise_fraction);
  if (trusted <= 0.0) return false;
  end = rig + ray * (trusted / length);
  return true;
}

// Azimuth bins of the lines of sight: half a degree, a few centimetres across at the
// range of furniture.
constexpr int kAzimuthBins = 720;

int azimuthBin(double azimuth) {
  azimuth = std::remainder(azimuth, 2.0 * kPi);  // in [-pi, pi]
  const int bin = static_cast<int>(std::floor((azimuth + kPi) / (2.0 * kPi) * kAzimuthBins));
  return std::clamp(bin, 0, kAzimuthBins - 1);
}

// The plan corners (room frame, counter-clockwise) of the local region [lo, hi] of a
// box whose frame has its origin at `origin` and is turned by `yaw`.
std::vector<Eigen::Vector2d> footprint(const Eigen::Vector3d& origin, double yaw, const Eigen::Vector3d& lo,
                                       const Eigen::Vector3d& hi) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::vector<Eigen::Vector2d> corners;
  for (const auto& [x, y] : {std::pair{lo.x(), lo.y()}, {hi.x(), lo.y()}, {hi.x(), hi.y()}, {lo.x(), hi.y()}}) {
    corners.emplace_back(origin.x() + c * x - s * y, origin.y() + s * x + c * y);
  }
  return corners;
}

// How far inside a box's faces its solid core starts: the carving inset, or the depth
// noise at the box's range if that is more (rays to points a little too far out must not
// prove a face's inside empty).
double insetAt(const Eigen::Vector3d& center, const HiddenSideParams& params) {
  const double noise = params.noise_sigmas * params.noise_fraction * (params.rig_position - center).norm();
  return std::max(params.inset_m, noise);
}

// How far (from the region's near end, along `axis` with `sign`) rays first enter the
// region [lo, hi]: the free_rays-th smallest, or infinity if fewer rays cross it.
// Everything is in the box's local frame: the rays run from the rig to the ends of their
// trusted stretches (trustedEnd); the box is [box_lo, box_hi].
// A ray that passes through the box itself contradicts the box (the point was seen
// through it: a stereo mismatch) and proves nothing about the space behind it.
double carvedDepth(const std::vector<Eigen::Vector3d>& ray_ends, const Eigen::Vector3d& rig_local,
                   const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& box_lo,
                   const Eigen::Vector3d& box_hi, int axis, int sign, const HiddenSideParams& params) {
  std::vector<double> entries;
  const double near_end = sign > 0 ? lo[axis] : hi[axis];
  for (const Eigen::Vector3d& end : ray_ends) {
    const double t = segmentEntry(rig_local, end, lo, hi);
    if (!std::isfinite(t) || std::isfinite(segmentEntry(rig_local, end, box_lo, box_hi))) continue;
    const Eigen::Vector3d at = rig_local + t * (end - rig_local);
    entries.push_back(std::max(0.0, sign * (at[axis] - near_end)));
  }
  if (entries.size() < params.free_rays) return kInf;
  const auto kth = entries.begin() + static_cast<std::ptrdiff_t>(params.free_rays - 1);
  std::nth_element(entries.begin(), kth, entries.end());
  return *kth;
}

// How far the box's side (local axis, sign) can move before its footprint leaves the room.
double roomLimit(const CuboidObject& box, int axis, int sign, const Eigen::Vector3d& room) {
  const Eigen::Vector2d u(std::cos(box.yaw_rad), std::sin(box.yaw_rad));
  const Eigen::Vector2d v(-u.y(), u.x());
  const Eigen::Vector2d direction = sign * (axis == 0 ? u : v);
  const auto corners = cuboidFootprint(box);
  double limit = kInf;
  for (const auto& c : corners) {
    // Only the corners on the moving side (ahead of the centre along the direction).
    if ((c - box.center_m.head<2>()).dot(direction) <= 0.0) continue;
    for (int k = 0; k < 2; ++k) {
      if (direction[k] > 1e-9) limit = std::min(limit, (room[k] - c[k]) / direction[k]);
      if (direction[k] < -1e-9) limit = std::min(limit, (0.0 - c[k]) / direction[k]);
    }
  }
  return std::max(0.0, limit);
}

}  // namespace

SightLines::SightLines(const std::vector<Eigen::Vector3d>& observed, const HiddenSideParams& params)
    : rig_(params.rig_position) {
  // One line per point, so that line i is point i; a point whose noise covers its whole
  // range proves nothing and goes in no bin.
  std::vector<int> bin_of(observed.size(), -1);
  ends_.resize(observed.size(), rig_);
  bin_start_.assign(kAzimuthBins + 1, 0);
  for (std::size_t i = 0; i < observed.size(); ++i) {
    if (!trustedEnd(rig_, observed[i], params, ends_[i])) continue;
    bin_of[i] = azimuthBin(std::atan2(ends_[i].y() - rig_.y(), ends_[i].x() - rig_.x()));
    ++bin_start_[static_cast<std::size_t>(bin_of[i]) + 1];
  }
  std::partial_sum(bin_start_.begin(), bin_start_.end(), bin_start_.begin());
  by_azimuth_.resize(bin_start_.back());
  std::vector<std::uint32_t> next(bin_start_.begin(), bin_start_.end() - 1);
  for (std::uint32_t i = 0; i < bin_of.size(); ++i) {
    if (bin_of[i] >= 0) by_azimuth_[next[static_cast<std::size_t>(bin_of[i])]++] = i;
  }
}

void SightLines::linesOver(const std::vector<Eigen::Vector2d>& corners, std::vector<std::uint32_t>& out) const {
  out.clear();
  const Eigen::Vector2d rig = rig_.head<2>();
  // Over the footprint (on its edge too): lines leave the rig in every direction.
  bool over = true;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const Eigen::Vector2d edge = corners[(k + 1) % corners.size()] - corners[k], to_rig = rig - corners[k];
    if (edge.x() * to_rig.y() - edge.y() * to_rig.x() < 1e-9) over = false;
  }
  // From outside a convex footprint its corners span its azimuths, less than half a turn;
  // a line crosses the prism only if its plan does, so only if its azimuth is in that span.
  // A span near half a turn (the rig next to an edge) takes every line, rounding aside.
  double first = 0.0, last = 0.0;
  const double a0 = std::atan2(corners[0].y() - rig.y(), corners[0].x() - rig.x());
  for (const auto& c : corners) {
    const double d = std::remainder(std::atan2(c.y() - rig.y(), c.x() - rig.x()) - a0, 2.0 * kPi);
    first = std::min(first, d), last = std::max(last, d);
  }
  if (!over && last - first < 0.9 * kPi) {
    // The bins one either side too: rounding at a bin's edge.
    const int bin_lo = azimuthBin(a0 + first) - 1;
    int bin_hi = azimuthBin(a0 + last) + 1;
    if (bin_hi < bin_lo) bin_hi += kAzimuthBins;  // across -pi
    for (int k = bin_lo; k <= bin_hi; ++k) {
      const auto bin = static_cast<std::size_t>((k + kAzimuthBins) % kAzimuthBins);
      out.insert(out.end(), by_azimuth_.begin() + bin_start_[bin], by_azimuth_.begin() + bin_start_[bin + 1]);
    }
    return;
  }
  out = by_azimuth_;
}

CuboidObject extendHiddenSides(CuboidObject box, const SightLines& lines, const OwnLines& own,
                               const HiddenSideParams& params) {
  // Work in the box's frame as fitted (centre at the origin, axes along its sides); the
  // box's bounds in it grow, the frame stays.
  const Eigen::Matrix3d to_local = Eigen::AngleAxisd(-box.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d origin = box.center_m;
  const auto local = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return to_local * (p - origin); };
  const Eigen::Vector3d rig = local(params.rig_position);
  // The carved regions stay clear of the box's other faces by their noise, lest rays to
  // the floor just in front of a face measured a little too far out prove its underside
  // empty.
  const double inset = insetAt(origin, params);
  Eigen::Vector3d bmin = -0.5 * box.size_m, bmax = 0.5 * box.size_m;
  // Every region carved below lies within the box grown by max_to_wall_m sideways and
  // down to the floor (give or take the 1 cm kept around a thin box's mid plane). A ray
  // that misses that bound enters none of them, and most of the room's rays miss it, so
  // the regions test only the others (each region all of them). The bound's 5 cm margin
  // is far beyond the rounding of the slab tests: the result is that of testing all.
  const double margin = 0.05;
  const Eigen::Vector3d reach_lo(bmin.x() - params.max_to_wall_m - margin, bmin.y() - params.max_to_wall_m - margin,
                                 std::min(-origin.z(), bmin.z()) - margin);
  const Eigen::Vector3d reach_hi(bmax.x() + params.max_to_wall_m + margin, bmax.y() + params.max_to_wall_m + margin,
                                 bmax.z() + margin);
  std::vector<Eigen::Vector3d> ray_ends;
  std::vector<std::uint32_t> candidates;
  lines.linesOver(footprint(origin, box.yaw_rad, reach_lo, reach_hi), candidates);
  for (const std::uint32_t i : candidates) {
    if (own.contains(i)) continue;
    const Eigen::Vector3d end = local(lines.end(i));
    if (std::isfinite(segmentEntry(rig, end, reach_lo, reach_hi))) ray_ends.push_back(end);
  }
  // Only a box square to the walls can stand flush against one.
  const double quarter = 0.5 * kPi;
  const bool square = std::abs(box.yaw_rad - quarter * std::round(box.yaw_rad / quarter)) < 1e-6;
  // The box's solid core (rays through it contradict it), the box shrunk by the inset but
  // never inside out: a box thinner than that keeps its mid plane.
  const auto core = [&](Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
    for (int k = 0; k < 3; ++k) {
      const double middle = 0.5 * (bmin[k] + bmax[k]);
      lo[k] = std::min(bmin[k] + inset, middle), hi[k] = std::max(bmax[k] - inset, middle);
    }
  };
  Eigen::Vector3d core_lo, core_hi;

  // Bottom: the floor under it is hidden unless rays reached below it.
  const double floor_local = -origin.z();
  if (bmin.z() - floor_local > 1e-9) {
    const Eigen::Vector3d lo(std::min(bmin.x() + inset, -0.01), std::min(bmin.y() + inset, -0.01), floor_local);
    const Eigen::Vector3d hi(std::max(bmax.x() - inset, 0.01), std::max(bmax.y() - inset, 0.01), bmin.z());
    core(core_lo, core_hi);
    if (!std::isfinite(carvedDepth(ray_ends, rig, lo, hi, core_lo, core_hi, 2, 1, params))) {
      bmin.z() = floor_local;
    }
  }

  for (int axis = 0; axis < 2; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      const int other = 1 - axis;
      const double face = sign > 0 ? bmax[axis] : bmin[axis];
      // A side is hidden unless the rig is in front of it.
      if (sign * (rig[axis] - face) > 0.0) continue;
      CuboidObject current = box;
      current.center_m = origin + to_local.transpose() * (0.5 * (bmin + bmax));
      current.size_m = bmax - bmin;
      const double to_room = roomLimit(current, axis, sign, params.room_size);
      const double reach = std::min(to_room, params.max_to_wall_m);
      if (reach <= 1e-6) continue;
      Eigen::Vector3d lo, hi;
      lo[axis] = sign > 0 ? face : face - reach;
      hi[axis] = sign > 0 ? face + reach : face;
      const double middle_other = 0.5 * (bmin[other] + bmax[other]), middle_z = 0.5 * (bmin.z() + bmax.z());
      lo[other] = std::min(bmin[other] + inset, middle_other - 0.01);
      hi[other] = std::max(bmax[other] - inset, middle_other + 0.01);
      lo.z() = std::min(bmin.z() + inset, middle_z - 0.01), hi.z() = std::max(bmax.z() - inset, middle_z + 0.01);
      core(core_lo, core_hi);
      const double carved = carvedDepth(ray_ends, rig, lo, hi, core_lo, core_hi, axis, sign, params);
      const double depth = bmax[axis] - bmin[axis];
      double grow = 0.0;
      if (square && carved >= reach && to_room <= params.max_to_wall_m) {
        grow = to_room;  // nothing seen between it and the wall: it stands against the wall
      } else if (depth < params.min_depth_m) {
        grow = std::min({params.min_depth_m - depth, carved, reach});
      }
      if (grow <= 0.0) continue;
      (sign > 0 ? bmax[axis] : bmin[axis]) += sign * grow;
    }
  }
  box.center_m = origin + to_local.transpose() * (0.5 * (bmin + bmax));
  box.size_m = bmax - bmin;
  return box;
}

std::size_t raysThroughBox(const CuboidObject& box, const SightLines& lines, const OwnLines& own,
                           const HiddenSideParams& params) {
  const Eigen::Matrix3d to_local = Eigen::AngleAxisd(-box.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d rig = to_local * (params.rig_position - box.center_m);
  // The core never turns inside out: a box thinner than twice the inset keeps its mid plane.
  const Eigen::Vector3d half = (0.5 * box.size_m.array() - insetAt(box.center_m, params)).max(0.0).matrix();
  std::vector<std::uint32_t> candidates;
  lines.linesOver(footprint(box.center_m, box.yaw_rad, -half, half), candidates);
  std::size_t count = 0;
  for (const std::uint32_t i : candidates) {
    if (own.contains(i)) continue;
    count += std::isfinite(segmentEntry(rig, to_local * (lines.end(i) - box.center_m), -half, half));
  }
  return count;
}

}  // namespace room_reverb::core::layout
