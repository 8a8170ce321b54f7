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

// The minimum over t in [0, 1] of a convex function, by golden-section search.
template <typename F>
double goldenMinimum(const F& f) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = 0.0, hi = 1.0;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int k = 0; k < 50; ++k) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = f(x2);
    }
  }
  return 0.5 * (lo + hi);
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
  // Over one edge: |s - p| + |p - l| is convex along it.
  for (const Edge& e : edges) {
    const double t = goldenMinimum([&](double u) { return (s - at(e, u)).norm() + (at(e, u) - l).norm(); });
    consider({at(e, t)});
  }
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
      double ta = 0.5, tb = 0.5;
      for (int round = 0; round < 8; ++round) {
        ta = goldenMinimum([&](double u) { return (s - at(a, u)).norm() + (at(a, u) - at(b, tb)).norm(); });
        tb = goldenMinimum([&](double u) { return (at(a, ta) - at(b, u)).norm() + (at(b, u) - l).norm(); });
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

OctaveBandValues edgeDiffractionGains(const EdgeDetour& detour, double speed_of_sound_m_s) {
  OctaveBandValues gains{};
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  for (int b = 0; b < kOctaveBandCount; ++b) {
    const double n = 2.0 * detour.path_difference_m * bands[static_cast<std::size_t>(b)].center_hz / speed_of_sound_m_s;
    gains[static_cast<std::size_t>(b)] = std::pow(10.0, -barrierLossDb(detour.shadowed ? n : -n) / 20.0);
  }
  return gains;
}

}  // namespace room_reverb::core
