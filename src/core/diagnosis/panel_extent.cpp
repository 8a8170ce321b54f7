#include "room_reverb/diagnosis/panel_extent.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <utility>

#include "room_reverb/diagnosis/unexplained_reflections.h"

namespace room_reverb::core {
namespace {

constexpr double kSupportMarginM = 0.25;  // round each point that saw the panel
constexpr double kDenialMarginM = 0.1;    // between a cut edge and the point it denies
constexpr double kRoomClearanceM = 0.05;
constexpr double kBoundStepM = 0.05;

Eigen::Vector2d inPlane(const PanelPlane& plane, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - plane.origin;
  return {d.dot(plane.u), d.dot(plane.v)};
}

// How far the plane reaches from the origin along `axis` (a unit vector in it) before it
// leaves the room or comes within kRoomClearanceM of a surface, up to kMaxPanelHalfM.
double reachAlong(const PanelPlane& plane, const Eigen::Vector3d& axis, const AcousticScene& scene) {
  double reach = 0.0;
  for (double s = kBoundStepM; s <= kMaxPanelHalfM + 1e-9; s += kBoundStepM) {
    const Eigen::Vector3d p = plane.origin + s * axis;
    if (!scene.isInside(p) || scene.distanceToNearestSurface(p) < kRoomClearanceM) break;
    reach = s;
  }
  return reach;
}

bool contains(const PanelExtent& e, const Eigen::Vector2d& q) {
  return q.x() > e.u_min && q.x() < e.u_max && q.y() > e.v_min && q.y() < e.v_max;
}

bool holds(const PanelExtent& outer, const PanelExtent& inner) {
  return outer.u_min <= inner.u_min && outer.u_max >= inner.u_max && outer.v_min <= inner.v_min &&
         outer.v_max >= inner.v_max;
}

void include(PanelExtent& e, const Eigen::Vector2d& q, double margin) {
  e.u_min = std::min(e.u_min, q.x() - margin);
  e.u_max = std::max(e.u_max, q.x() + margin);
  e.v_min = std::min(e.v_min, q.y() - margin);
  e.v_max = std::max(e.v_max, q.y() + margin);
}

// One side [lo, hi] of a panel `length` long, centred in [allowed_lo, allowed_hi] as far as
// holding [need_lo, need_hi] lets it.
std::pair<double, double> placeSide(double allowed_lo, double allowed_hi, double need_lo, double need_hi, double length) {
  length = std::clamp(length, need_hi - need_lo, std::max(need_hi - need_lo, allowed_hi - allowed_lo));
  double lo = 0.5 * (allowed_lo + allowed_hi) - 0.5 * length;
  lo = std::clamp(lo, need_hi - length, need_lo);  // hold the support
  return {lo, lo + length};
}

}  // namespace

std::optional<WitnessPoint> witnessPoint(const PanelPlane& plane, const PanelWitness& witness, double c) {
  const Eigen::Vector3d S = witness.pair.source_m, R = witness.pair.receiver_m;
  const double ds = (S - plane.origin).dot(plane.normal), dr = (R - plane.origin).dot(plane.normal);
  // On opposite sides the panel would block the direct sound, which every measurement has.
  if (ds * dr < 0.0) return WitnessPoint{inPlane(plane, S + (R - S) * (ds / (ds - dr))), false};
  if (std::abs(ds) < 1e-6 || std::abs(dr) < 1e-6) return std::nullopt;
  // The image source behind the plane (a thin panel reflects from either face); the
  // reflection point is where the line from it to the receiver crosses the plane.
  const Eigen::Vector3d image = S - 2.0 * ds * plane.normal;
  const Eigen::Vector3d Q = image + (R - image) * (ds / (ds + dr));
  const double direct = (R - S).norm(), reflected = (R - image).norm();
  const double delay = (reflected - direct) / c, level_db = 20.0 * std::log10(direct / reflected);
  if (delay > kStrongReflectionLatestS || level_db < kStrongReflectionLevelDb) return std::nullopt;
  SpecularPath path;
  path.order = 1;
  path.delay_s = reflected / c;
  path.arrival_direction = (Q - R).normalized();
  bool matched = false, confirmed = false;
  for (const RelativeReflection& r : witness.reflections) {
    if (!pathMatchesReflection(path, direct / c, r)) continue;
    matched = true;
    // A measured reflection the model already explains (a wall's, at the same time and
    // direction) says nothing about the panel.
    confirmed = confirmed || !explainedBySpecularPath(witness.paths, r);
  }
  if (matched && !confirmed) return std::nullopt;
  return WitnessPoint{inPlane(plane, Q), confirmed};
}

PanelBounds panelBounds(const PanelPlane& plane, const std::vector<Eigen::Vector3d>& support,
                        const std::vector<PanelWitness>& witnesses, const AcousticScene& scene, double c) {
  PanelBounds b;
  b.support = {-kSupportMarginM, kSupportMarginM, -kSupportMarginM, kSupportMarginM};
  for (const Eigen::Vector3d& p : support) include(b.support, inPlane(plane, p), kSupportMarginM);
  std::vector<Eigen::Vector2d> denied;
  for (const PanelWitness& w : witnesses) {
    const std::optional<WitnessPoint> point = witnessPoint(plane, w, c);
    if (point && point->confirmed) include(b.support, point->at, kSupportMarginM);
    if (point && !point->confirmed) denied.push_back(point->at);
  }
  // What may be: the prior size, stopped by the room, and at least the support.
  b.allowed = {-reachAlong(plane, -plane.u, scene), reachAlong(plane, plane.u, scene),
               -reachAlong(plane, -plane.v, scene), reachAlong(plane, plane.v, scene)};
  include(b.allowed, {b.support.u_min, b.support.v_min}, 0.0);
  include(b.allowed, {b.support.u_max, b.support.v_max}, 0.0);
  std::sort(denied.begin(), denied.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& q) { return a.norm() < q.norm(); });
  for (const Eigen::Vector2d& q : denied) {
    if (!contains(b.allowed, q)) continue;
    // The four cuts that would leave q outside, each only if the support stays inside.
    std::array<PanelExtent, 4> cuts{b.allowed, b.allowed, b.allowed, b.allowed};
    cuts[0].u_max = q.x() - kDenialMarginM;
    cuts[1].u_min = q.x() + kDenialMarginM;
    cuts[2].v_max = q.y() - kDenialMarginM;
    cuts[3].v_min = q.y() + kDenialMarginM;
    const PanelExtent* best = nullptr;
    for (const PanelExtent& cut : cuts) {
      if (holds(cut, b.support) && (!best || cut.width() * cut.height() > best->width() * best->height())) best = &cut;
    }
    if (best) b.allowed = *best;
  }
  return b;
}

PanelExtent placePanel(const PanelBounds& bounds, double side_m) {
  const PanelExtent& a = bounds.allowed;
  const PanelExtent& s = bounds.support;
  PanelExtent e;
  std::tie(e.u_min, e.u_max) = placeSide(a.u_min, a.u_max, s.u_min, s.u_max, side_m);
  std::tie(e.v_min, e.v_max) = placeSide(a.v_min, a.v_max, s.v_min, s.v_max, side_m);
  return e;
}

}  // namespace room_reverb::core
