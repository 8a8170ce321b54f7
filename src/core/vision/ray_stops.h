#pragma once
// What the rig's rays stop on, by direction, and where the rays aimed past a ceiling's
// ranged edge stop: the wall, when the ceiling near it has no range of its own.
//
// A ceiling's ranged points can end short of the wall: a light panel glowing flat, or a
// plain ceiling seen at a grazing angle near a far wall, gives the stereo nothing to match,
// and the ceiling's density steps down there as it would at a wall. Where no wall plane
// stands at that edge (the wall behind a fridge, shelving or a table), the edge alone puts
// the wall short (cluttered development room 7 at 1024 x 512: 0.86 m, behind a hanging
// light panel). The rays the rig aims well past the edge at the ceiling's height tell the
// two apart: past a wall they stop on it (a point nearer than the ceiling would be); past
// an unranged stretch of ceiling they fly on to the wall beyond it.
#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

#include "room_box_fit.h"

namespace room_reverb::core::layout {

// The nearest point seen in each cell of a grid of directions (azimuth x elevation) around
// the rig at the origin of the aligned frame.
class RayStops {
 public:
  explicit RayStops(const std::vector<WeightedPoint>& points, double cell_deg = 0.5);
  // The nearest point seen in the direction of `target` (its cell), or nullopt where no
  // ray came back.
  std::optional<Eigen::Vector3f> along(const Eigen::Vector3d& target) const;

 private:
  std::size_t cell(const Eigen::Vector3d& direction) const;
  double cell_rad_;
  std::size_t azimuth_cells_, elevation_cells_;
  std::vector<Eigen::Vector3f> nearest_;
  std::vector<float> range_;  // of nearest_; infinity where nothing came back
};

// Where the rays aimed well past a ceiling's edge stop, along `axis` (0: x, 1: y) on the low
// (`below`) or high side: rays aimed at the ceiling (height ceiling_z) at distances from
// reach_m / 2 to reach_m beyond `edge` (5 cm steps) and at lateral positions across the
// middle 80 % of `lateral` (the room's extent along the wall, 10 cm steps). Past a wall at
// the edge they stop on it; past an unranged stretch of ceiling they fly on to the wall
// beyond it. Rays aimed just past the edge are not asked: a light hanging there stops them.
// A ray's stop counts where it lies between `tolerance` inside the edge and `tolerance`
// short of its target (a stop further inside is furniture or a light in the room). With
// at least a quarter of the rays (and 20) stopping so, half of the stops within twice
// `tolerance` of their median (one surface), the wall is that median when it lies more
// than `tolerance` beyond the edge; otherwise nullopt (the wall is at the edge). Where too
// few rays stop (they come back with nothing, or on the ceiling where they were aimed:
// the unranged stretch runs on past the window, as a plain ceiling under sensor noise
// does), the next window of reach_m / 2 further out is asked, up to max_beyond_m past the
// edge; nullopt when none holds enough stops (no evidence).
// Distances are positive (from the rig).
std::optional<double> wallWhereCeilingRaysStop(const RayStops& stops, int axis, bool below, double edge,
                                               double ceiling_z, const std::pair<double, double>& lateral,
                                               double tolerance, double reach_m = 2.0, double max_beyond_m = 6.0);

}  // namespace room_reverb::core::layout
