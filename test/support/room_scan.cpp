#include "room_scan.h"

#include <cmath>
#include <limits>
#include <random>

namespace room_reverb::test {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// Entry distance of a ray into an upright cuboid (slabs in the cuboid's own frame), or
// infinity if it misses or the cuboid is behind.
double cuboidEntry(const core::CuboidObject& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  const Eigen::Matrix3d to_local = Eigen::AngleAxisd(-box.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d o = to_local * (origin - box.center_m);
  const Eigen::Vector3d d = to_local * direction;
  double enter = -kInf, leave = kInf;
  for (int a = 0; a < 3; ++a) {
    const double half = 0.5 * box.size_m[a];
    if (std::abs(d[a]) < 1e-12) {
      if (std::abs(o[a]) > half) return kInf;
      continue;
    }
    double t0 = (-half - o[a]) / d[a], t1 = (half - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  return (enter <= leave && enter > 0.0) ? enter : kInf;
}

// Distance to where a ray from inside leaves the box [0, size], and through which face.
double boxExit(const Eigen::Vector3d& size, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
               int* face) {
  // Face index per axis and side, in kRoomSurfaceNames order (floor, ceiling, x-, x+, y-, y+).
  constexpr int kFace[3][2] = {{2, 3}, {4, 5}, {0, 1}};
  double best = kInf;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(direction[a]) < 1e-12) continue;
    const bool up = direction[a] > 0.0;
    const double t = ((up ? size[a] : 0.0) - origin[a]) / direction[a];
    if (t < best) best = t, *face = kFace[a][up ? 1 : 0];
  }
  return best;
}

}  // namespace

double castRoomRay(const core::RoomModel& model, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                   int* face, int* object) {
  *object = -1;
  double t = boxExit(model.size_m, origin, direction, face);
  if (*face == 1 && !model.has_ceiling) t = kInf, *face = -1;
  for (std::size_t k = 0; k < model.objects.size(); ++k) {
    const double hit = cuboidEntry(model.objects[k], origin, direction);
    if (hit < t) t = hit, *face = -1, *object = static_cast<int>(k);
  }
  return t;
}

RoomScanOptions stereoLikeScanOptions(std::uint32_t seed) {
  RoomScanOptions options;
  options.rays = 300000;
  options.range_noise_fraction = 0.01;
  options.stray_fraction = 0.03;
  options.polar_cap_deg = 10.0;
  options.seed = seed;
  return options;
}

RoomScan scanRoomModel(const core::RoomModel& model, const RoomScanOptions& options) {
  RoomScan scan;
  scan.cloud.frame = "rig";
  scan.cloud.has_color = true;
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::Matrix3d rig_to_room = model.rig_rotation.toRotationMatrix();
  const Eigen::Vector3d& origin = model.rig_position_m;
  // Fibonacci sphere: evenly spread directions, no clumping at the poles.
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  const std::size_t n = options.rays;
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(n);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Eigen::Vector3d rig_dir(r * std::cos(golden * static_cast<double>(i)),
                                  r * std::sin(golden * static_cast<double>(i)), z);
    if (std::abs(z) > std::cos(options.polar_cap_deg * kPi / 180.0)) continue;
    const Eigen::Vector3d dir = rig_to_room * rig_dir;
    int face = -1, object = -1;
    double t = castRoomRay(model, origin, dir, &face, &object);
    const bool stray = uniform(rng) < options.stray_fraction;
    bool through_window = false;
    for (const ScanWindow& w : options.windows) {
      if (face != w.face || stray) continue;
      const Eigen::Vector3d hit = origin + t * dir;
      const int along = w.face < 4 ? 1 : 0;  // x walls run along y, y walls along x
      if (hit[along] < w.from_m || hit[along] > w.to_m || hit.z() < w.bottom_m || hit.z() > w.top_m) continue;
      const int across = 1 - along;
      const double facade = hit[across] + (w.face % 2 == 1 ? 1.0 : -1.0) * w.facade_distance_m;
      t = (facade - origin[across]) / dir[across];
      face = -1, through_window = true;
    }
    if (stray) {
      int exit_face = -1;
      const double exit = boxExit(model.size_m, origin, dir, &exit_face);
      if (exit_face == 1 && !model.has_ceiling) continue;
      t = exit + 0.1 + uniform(rng) * (options.stray_depth_m - 0.1);
      face = -1, object = -1;
    }
    if (!std::isfinite(t)) continue;  // open sky
    t *= 1.0 + options.range_noise_fraction * gauss(rng);
    core::CloudPoint point;
    point.p = (t * rig_dir).cast<float>();
    // Colours by kind of surface, so a colour-reading step has something to read.
    const std::uint8_t shade = object >= 0 ? 90 : (face == 0 ? 150 : (face == 1 ? 240 : 200));
    point.r = point.g = point.b = shade;
    if (options.hints && !stray && !through_window) {
      using core::SurfaceHint;
      const SurfaceHint hint = object >= 0 ? SurfaceHint::object
                               : face == 0 ? SurfaceHint::floor
                               : face == 1 ? SurfaceHint::ceiling
                                           : SurfaceHint::wall;
      point.hint = static_cast<std::uint16_t>(hint);
    }
    scan.cloud.points.push_back(point);
    scan.face.push_back(face);
    scan.object.push_back(object);
    scan.stray.push_back(stray || through_window);
  }
  return scan;
}

}  // namespace room_reverb::test
