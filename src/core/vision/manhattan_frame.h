#pragma once
// The room's yaw in the rig frame: the direction of its walls, modulo 90 degrees (a
// Manhattan world: walls meet at right angles, the cloud is already levelled).
#include <Eigen/Core>
#include <vector>

namespace room_reverb::core::layout {

// Wraps an angle into [-pi/4, pi/4): the wall directions repeat every 90 degrees.
double wrapQuarterTurn(double angle_rad);

// Coarse-to-fine search for the yaw that makes the plan view of the points sharpest: the
// sum of squared bin counts of the histograms of x' and y' (the points rotated by -yaw) is
// largest when every wall falls into as few bins as possible. A histogram of positions
// needs no surface normals, which noisy stereo points at a few cm spacing do not give
// reliably. Returns the yaw in [-pi/4, pi/4).
double sharpestPlanYaw(const std::vector<Eigen::Vector2d>& plan_points, double bin_m);

// One wall's points for the line-fit refinement.
struct WallPoints {
  std::vector<Eigen::Vector2d> plan;  // plan coordinates in the rig frame
};

// The yaw refined by fitting a line to each wall's points (principal axis of their plan
// coordinates, one pass of trimming at 3 sigma) and averaging the four directions modulo
// 90 degrees, each weighted by its inverse variance (points x spread along the wall over
// the spread across it). Walls with fewer than 10 points are skipped; if none is left the
// yaw comes back unchanged.
double refineYawFromWalls(double yaw_rad, const std::vector<WallPoints>& walls);

}  // namespace room_reverb::core::layout
