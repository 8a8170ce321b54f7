#include "room_reverb/common/convex_polygons.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace room_reverb::core {
namespace {

// A point this close to a line is on it: footprints of objects fitted flush against each
// other share edges only up to rounding of their rotations.
constexpr double kOnLineM = 1e-9;

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// +1 left of the directed line a -> b, -1 right, 0 on it.
int sideOf(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = b - a;
  const double distance = cross(ab, p - a) / ab.norm();
  if (std::abs(distance) <= kOnLineM) return 0;
  return distance > 0.0 ? 1 : -1;
}

}  // namespace

double polygonArea(const Polygon2d& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) twice += cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  return 0.5 * std::abs(twice);
}

Polygon2d clipToConvex(Polygon2d subject, const Polygon2d& clip) {
  for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const Eigen::Vector2d& a = clip[e];
    const Eigen::Vector2d edge = clip[(e + 1) % clip.size()] - a;
    Polygon2d kept;
    kept.reserve(subject.size() + 4);
    for (std::size_t i = 0; i < subject.size(); ++i) {
      const Eigen::Vector2d& p = subject[i];
      const Eigen::Vector2d& q = subject[(i + 1) % subject.size()];
      const double side_p = cross(edge, p - a);
      const double side_q = cross(edge, q - a);
      if (side_p >= 0.0) kept.push_back(p);
      // An edge crossing the clip line contributes its crossing point.
      if ((side_p >= 0.0) != (side_q >= 0.0)) kept.push_back(p + (q - p) * (side_p / (side_p - side_q)));
    }
    subject = std::move(kept);
  }
  return subject;
}

// Green's theorem over the union's boundary: the boundary is made of the parts of the
// polygons' edges that lie outside every other polygon, and the area is half the sum of
// cross(a, b) over them (KACTL's PolygonUnion, with a tolerance for shared edges).
double unionArea(const std::vector<Polygon2d>& polygons) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const Polygon2d& pi = polygons[i];
    for (std::size_t v = 0; v < pi.size(); ++v) {
      const Eigen::Vector2d& a = pi[v];
      const Eigen::Vector2d& b = pi[(v + 1) % pi.size()];
      const Eigen::Vector2d ab = b - a;
      if (ab.norm() <= kOnLineM) continue;
      // Where along a -> b (0..1) the number of other polygons covering the edge changes.
      std::vector<std::pair<double, int>> events = {{0.0, 0}, {1.0, 0}};
      for (std::size_t j = 0; j < polygons.size(); ++j) {
        if (j == i) continue;
        const Polygon2d& pj = polygons[j];
        for (std::size_t u = 0; u < pj.size(); ++u) {
          const Eigen::Vector2d& c = pj[u];
          const Eigen::Vector2d& d = pj[(u + 1) % pj.size()];
          if ((d - c).norm() <= kOnLineM) continue;
          const int sc = sideOf(a, b, c), sd = sideOf(a, b, d);
          if (sc != sd) {
            const double sa = cross(d - c, a - c), sb = cross(d - c, b - c);
            if (std::min(sc, sd) < 0) events.emplace_back(sa / (sa - sb), sc > sd ? 1 : -1);
          } else if (sc == 0 && j < i && ab.dot(d - c) > 0.0) {
            // The same edge run the same way: the lower-numbered polygon keeps it.
            events.emplace_back((c - a).dot(ab) / ab.squaredNorm(), 1);
            events.emplace_back((d - a).dot(ab) / ab.squaredNorm(), -1);
          }
        }
      }
      std::sort(events.begin(), events.end());
      for (auto& event : events) event.first = std::clamp(event.first, 0.0, 1.0);
      double uncovered = 0.0;
      int cover = events[0].second;
      for (std::size_t k = 1; k < events.size(); ++k) {
        if (cover == 0) uncovered += events[k].first - events[k - 1].first;
        cover += events[k].second;
      }
      twice += cross(a, b) * uncovered;
    }
  }
  return 0.5 * twice;
}

}  // namespace room_reverb::core
