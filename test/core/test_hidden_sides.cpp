// The furniture fit's lines of sight (src/core/vision/hidden_sides.h): binned by azimuth so
// that a box visits only the lines that can cross it, with the result of testing them all.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "hidden_sides.h"

namespace {

using namespace room_reverb::core;
using namespace room_reverb::core::layout;

constexpr double kPi = 3.14159265358979323846;

// Whether the segment a -> b meets the box [lo, hi] (slab method, written here apart from
// the library's).
bool segmentMeetsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi) {
  double enter = 0.0, leave = 1.0;
  for (int k = 0; k < 3; ++k) {
    const double d = b[k] - a[k];
    if (std::abs(d) < 1e-12) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    const double t0 = std::min((lo[k] - a[k]) / d, (hi[k] - a[k]) / d);
    const double t1 = std::max((lo[k] - a[k]) / d, (hi[k] - a[k]) / d);
    enter = std::max(enter, t0), leave = std::min(leave, t1);
    if (enter > leave) return false;
  }
  return true;
}

struct Scene {
  HiddenSideParams params;
  std::vector<Eigen::Vector3d> points;
};

// Points scattered through a 12 x 9 x 3 m room around a rig at (5, 4, 1.4).
Scene scatteredRoom(unsigned seed) {
  Scene s;
  s.params.rig_position = Eigen::Vector3d(5.0, 4.0, 1.4);
  s.params.room_size = Eigen::Vector3d(12.0, 9.0, 3.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(0.0, 12.0), y(0.0, 9.0), z(0.0, 3.0);
  for (int i = 0; i < 20000; ++i) s.points.emplace_back(x(rng), y(rng), z(rng));
  // Points straight above and below the rig: lines with no horizontal extent.
  s.points.emplace_back(5.0, 4.0, 3.0);
  s.points.emplace_back(5.0, 4.0, 0.0);
  return s;
}

// The plan corners of a box turned by yaw about its centre.
std::vector<Eigen::Vector2d> corners(const CuboidObject& box) {
  const double c = std::cos(box.yaw_rad), s = std::sin(box.yaw_rad);
  const Eigen::Vector3d h = 0.5 * box.size_m;
  std::vector<Eigen::Vector2d> out;
  for (const auto& [x, y] : {std::pair{-h.x(), -h.y()}, {h.x(), -h.y()}, {h.x(), h.y()}, {-h.x(), h.y()}}) {
    out.emplace_back(box.center_m.x() + c * x - s * y, box.center_m.y() + s * x + c * y);
  }
  return out;
}

CuboidObject randomBox(std::mt19937& rng) {
  std::uniform_real_distribution<double> x(0.3, 11.7), y(0.3, 8.7), side(0.1, 2.5), height(0.2, 2.0), yaw(-kPi, kPi);
  CuboidObject box;
  box.size_m = Eigen::Vector3d(side(rng), side(rng), height(rng));
  box.center_m = Eigen::Vector3d(x(rng), y(rng), 0.5 * box.size_m.z());
  box.yaw_rad = yaw(rng);
  return box;
}

TEST(SightLines, EveryLineThatCrossesABoxIsVisited) {
  const Scene scene = scatteredRoom(3);
  const SightLines lines(scene.points, scene.params);
  ASSERT_EQ(lines.size(), scene.points.size());
  std::mt19937 rng(11);
  std::vector<std::uint32_t> visited;
  double visited_share = 0.0;
  int boxes = 0, crossing = 0;
  for (int trial = 0; trial < 400; ++trial) {
    CuboidObject box = randomBox(rng);
    // Every tenth box straddles the azimuth -pi behind the rig (the bins' wrap), and some
    // stand over the rig.
    if (trial % 10 == 0) box.center_m.head<2>() = Eigen::Vector2d(2.0, 4.0 + 0.05 * (trial % 3));
    if (trial % 25 == 0) box.center_m.head<2>() = scene.params.rig_position.head<2>();
    lines.linesOver(corners(box), visited);
    std::vector<bool> in(lines.size(), false);
    for (const std::uint32_t i : visited) in[i] = true;
    const Eigen::Matrix3d to_local = Eigen::AngleAxisd(-box.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d rig = to_local * (scene.params.rig_position - box.center_m);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const Eigen::Vector3d end = to_local * (lines.end(i) - box.center_m);
      if (!segmentMeetsBox(rig, end, -0.5 * box.size_m, 0.5 * box.size_m)) continue;
      ++crossing;
      ASSERT_TRUE(in[i]) << "box " << trial << " at (" << box.center_m.transpose() << "), line " << i << " crosses it";
    }
    visited_share += static_cast<double>(visited.size()) / static_cast<double>(lines.size());
    ++boxes;
  }
  EXPECT_GT(crossing, 10000);  // the check above had work to do
  // Most lines are skipped: a box a few metres away subtends a few tens of degrees. These
  // boxes visit 14.6 % of the lines on average (every 25th stands over the rig and visits
  // all of them); without the bins every box visits all.
  EXPECT_LT(visited_share / boxes, 0.2);
}

TEST(SightLines, RaysThroughABoxAreCountedAsByTestingEveryLine) {
  const Scene scene = scatteredRoom(5);
  const SightLines lines(scene.points, scene.params);
  std::vector<std::int32_t> owner(scene.points.size(), -1);
  for (std::size_t i = 0; i < owner.size(); i += 7) owner[i] = 1;  // a seventh of the lines are the box's own
  std::mt19937 rng(17);
  for (int trial = 0; trial < 200; ++trial) {
    const CuboidObject box = randomBox(rng);
    const Eigen::Matrix3d to_local = Eigen::AngleAxisd(-box.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d rig = to_local * (scene.params.rig_position - box.center_m);
    const double noise = scene.params.noise_sigmas * scene.params.noise_fraction;
    const double inset = std::max(scene.params.inset_m, noise * (scene.params.rig_position - box.center_m).norm());
    const Eigen::Vector3d half = (0.5 * box.size_m.array() - inset).max(0.0).matrix();
    std::size_t expected = 0;
    for (std::size_t i = 0; i < scene.points.size(); ++i) {
      if (owner[i] == 1) continue;
      // Each ray counts up to its point's noise short of the point.
      const Eigen::Vector3d q = scene.points[i];
      const Eigen::Vector3d end = scene.params.rig_position + (1.0 - noise) * (q - scene.params.rig_position);
      expected += segmentMeetsBox(rig, to_local * (end - box.center_m), -half, half);
    }
    EXPECT_EQ(raysThroughBox(box, lines, OwnLines{&owner, 1, 1}, scene.params), expected) << "box " << trial;
  }
}

}  // namespace
