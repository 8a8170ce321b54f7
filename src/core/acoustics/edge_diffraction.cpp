#include "room_reverb/acoustics/edge_diffraction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
// A leg that only grazes a face or an edge stays out: the interior is shrunk by this much.
constexpr double kSurfaceToleranceM = 1e-6;
constexpr double kMaxLossDb = 20.0;
// Kurze and Anderson's lit-side form reaches 0 dB at x = sqrt(2 pi |N|) of about 1.1.
constexpr double kLitLimit = 0.2;

// Slab test of the segment a + t (b - a), t in [0, 1], against the box |x_i| < half_i.
bool segmentCrossesBox(const Eigen::Vector3d& half, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  double t_in = 0.0, t_out = 1.0;
  const Eigen::Vector3d d = b - a;
  for (int i = 0; i < 3; ++i) {
    const double h = half[i] - kSurfaceToleranceM;
    if (h <= 0.0) return false;
    if (std::abs(d[i]) < 1e-15) {
      if (std::abs(a[i]) >= h) return false;
      continue;
    }
    double t0 = (-h - a[i]) / d[i], t1 = (h - a[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    t_in = std::max(t_in, t0);
    t_out = std::min(t_out, t1);
    if (t_in >= t_out) return false;
  }
  return true;
}

}  // namespace

bool segmentCrossesCuboid(const CuboidObject& object, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return segmentCrossesBox(0.5 * object.size_m, toCuboidFrame(object, a), toCuboidFrame(object, b));
}

namespace {

struct Edge {
  Eigen::Vector3d from, to;  // in the cuboid's frame
};

// The twelve edges of the box |x_i| <= half_i: along each axis, at the four sign
// combinations of the other two.
std::array<Edge, 12> boxEdges(const Eigen::Vector3d& half) {
  std::array<Edge, 12> edges;
  std::size_t n = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (const double su : {-1.0, 1.0}) {
      for (const double sv : {-1.0, 1.0}) {
        Eigen::Vector3d a = Eigen::Vector3d::Zero();
        a[u] = su * half[u];
        a[v] = sv * half[v];
        edges[n] = {a, a};
        edges[n].from[axis] = -half[axis];
        edges[n].to[axis] = half[axis];
        ++n;
      }
    }
  }
  return edges;
}

// Where on the edge e (at e.from + t (e.to - e.from), t in [0, 1]) the way x -> edge -> y
// is shortest. Turning the plane through the edge and y about the edge until it holds x
// on the other side makes the shortest way a straight line; it meets the edge's line at
// the parameter below, and since the length is convex along the edge, the nearest end of
// the edge when that lies beyond it. Exact and without iteration: a walking listener
// asks for every edge of every object at each pose.
double shortestOnEdge(const Edge& e, const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
  const Eigen::Vector3d axis = e.to - e.from;
  const double length = axis.norm();
  const Eigen::Vector3d u = axis / length;
  const double x_along = (x - e.from).dot(u), y_along = (y - e.from).dot(u);
  const double x_off = ((x - e.from) - x_along * u).norm(), y_off = ((y - e.from) - y_along * u).norm();
  const double sum = x_off + y_off;
  const double at = sum > 0.0 ? x_along + (y_along - x_along) * x_off / sum : x_along;
  return std::clamp(at / length, 0.0, 1.0);
}

// The distance from x to the nearest point of the edge.
double distanceToEdge(const Edge& e, const Eigen::Vector3d& x) {
  const Eigen::Vector3d axis = e.to - e.from;
  const double t = std::clamp((x - e.from).dot(axis) / axis.squaredNorm(), 0.0, 1.0);
  return (x - (e.from + t * axis)).norm();
}

}  // namespace

std::optional<EdgeDetour> shortestEdgeDetour(const CuboidObject& object, const Eigen::Vector3d& source,
                                             const Eigen::Vector3d& listener) {
  const Eigen::Vector3d half = 0.5 * object.size_m;
  if ((half.array() <= kSurfaceToleranceM).any()) return std::nullopt;
  const Eigen::Vector3d s = toCuboidFrame(object, source), l = toCuboidFrame(object, listener);
  if ((s.cwiseAbs().array() < half.array()).all() || (l.cwiseAbs().array() < half.array()).all()) return std::nullopt;
  const std::array<Edge, 12> edges = boxEdges(half);
  const auto at = [](const Edge& e, double t) -> Eigen::Vector3d { return e.from + t * (e.to - e.from); };
  std::optional<EdgeDetour> best;
  const auto consider = [&](const std::vector<Eigen::Vector3d>& turns) {
    Eigen::Vector3d previous = s;
    double total = 0.0;
    for (const Eigen::Vector3d& p : turns) {
      if (segmentCrossesBox(half, previous, p)) return;
      total += (p - previous).norm();
      previous = p;
    }
    if (segmentCrossesBox(half, previous, l)) return;
    total += (l - previous).norm();
    if (best && best->length_m <= total) return;
    EdgeDetour detour;
    for (const Eigen::Vector3d& p : turns) detour.turns.push_back(fromCuboidFrame(object, p));
    detour.length_m = total;
    best = detour;
  };
  // Over one edge.
  for (const Edge& e : edges) consider({at(e, shortestOnEdge(e, s, l))});
  // Across one face, over two of its opposite, parallel edges (a box thicker than the
  // line of sight's clearance): convex in both positions, minimised one at a time.
  for (std::size_t i = 0; i < edges.size(); ++i) {
    for (std::size_t j = 0; j < edges.size(); ++j) {
      const Edge& a = edges[i];
      const Edge& b = edges[j];
      const Eigen::Vector3d offset = b.from - a.from;
      // Parallel and sharing a face: the same direction, apart along one axis only.
      if (i == j || (a.to - a.from).cross(b.to - b.from).norm() > 1e-12) continue;
      if ((offset.array().abs() > 1e-12).count() != 1) continue;
      // No way over both is shorter than its three straight lower bounds: a way already
      // found that short makes the search pointless (in view, the way over one edge
      // nearly always is).
      if (best && distanceToEdge(a, s) + offset.norm() + distanceToEdge(b, l) >= best->length_m) continue;
      double ta = 0.5, tb = 0.5;
      for (int round = 0; round < 8; ++round) {
        ta = shortestOnEdge(a, s, at(b, tb));
        tb = shortestOnEdge(b, at(a, ta), l);
      }
      consider({at(a, ta), at(b, tb)});
    }
  }
  if (best) {
    best->path_difference_m = std::max(0.0, best->length_m - (listener - source).norm());
    best->shadowed = segmentCrossesBox(half, s, l);
  }
  return best;
}

double barrierLossDb(double fresnel_number) {
  const double x = std::sqrt(2.0 * kPi * std::abs(fresnel_number));
  if (fresnel_number >= 0.0) {
    if (x < 1e-9) return 5.0;
    return std::min(kMaxLossDb, 5.0 + 20.0 * std::log10(x / std::tanh(x)));
  }
  if (-fresnel_number >= kLitLimit) return 0.0;
  return std::max(0.0, 5.0 + 20.0 * std::log10(x / std::tan(x)));
}

OctaveBandValues edgeDiffractionGains(const EdgeDetour& detour, double speed_of_sound_m_s,
                                      const OctaveBandValues& band_centres_hz) {
  OctaveBandValues gains{};
  for (int b = 0; b < kOctaveBandCount; ++b) {
    const double n = 2.0 * detour.path_difference_m * band_centres_hz[b] / speed_of_sound_m_s;
    gains[static_cast<std::size_t>(b)] = std::pow(10.0, -barrierLossDb(detour.shadowed ? n : -n) / 20.0);
  }
  return gains;
}

std::optional<DirectSoundPast> directSoundPastObjects(const std::vector<CuboidObject>& objects,
                                                      const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                                                      bool in_view, double speed_of_sound_m_s,
                                                      const OctaveBandValues& band_centres_hz) {
  DirectSoundPast chosen;
  chosen.gains.fill(1.0);
  // In view, an object far from the line of sight costs nothing and is passed by without
  // its detour: no point of it is nearer the line through source and listener than h, its
  // centre's distance less its half-diagonal, so every way over it is at least
  // 2 sqrt((d / 2)^2 + h^2) - d longer than d (the spheroid with the two as foci), and
  // that far the lit side's loss is 0 in the lowest band.
  static const double lowest_hz = standardBands(BandResolution::kOctave).front().center_hz;
  const double clear_m = kLitLimit * speed_of_sound_m_s / (2.0 * lowest_hz);
  const Eigen::Vector3d line = listener - source;
  const double d = line.norm();
  for (const CuboidObject& object : objects) {
    if (in_view && d > 0.0) {
      const Eigen::Vector3d off = object.center_m - source;
      const double h = (off - off.dot(line) / (d * d) * line).norm() - 0.5 * object.size_m.norm();
      if (h > 0.0 && 2.0 * std::sqrt(0.25 * d * d + h * h) - d > clear_m) continue;
    }
    const std::optional<EdgeDetour> detour = shortestEdgeDetour(object, source, listener);
    if (!detour || detour->shadowed == in_view) continue;
    if (!in_view) {
      // Around this object's edge, no other object in the way.
      bool clear = true;
      Eigen::Vector3d from = source;
      for (std::size_t leg = 0; leg <= detour->turns.size(); ++leg) {
        const Eigen::Vector3d to = leg < detour->turns.size() ? detour->turns[leg] : listener;
        for (const CuboidObject& other : objects) clear = clear && !segmentCrossesCuboid(other, from, to);
        from = to;
      }
      if (!clear) continue;
    }
    const OctaveBandValues gains = edgeDiffractionGains(*detour, speed_of_sound_m_s);
    if (in_view && gains[0] == 1.0) continue;  // clear of its shadow in every band (the lowest the last)
    if (!chosen.detour || gains[4] < chosen.gains[4]) {
      chosen.detour = detour;
      chosen.gains = gains;
    }
  }
  if (!in_view && !chosen.detour) return std::nullopt;
  chosen.bent = !in_view;
  // The edge is chosen at the octaves' centres above, so that every third-octave view of a
  // scene hears the same path (the views' responses are joined path by path).
  if (chosen.detour) chosen.gains = edgeDiffractionGains(*chosen.detour, speed_of_sound_m_s, band_centres_hz);
  return chosen;
}

}  // namespace room_reverb::core
