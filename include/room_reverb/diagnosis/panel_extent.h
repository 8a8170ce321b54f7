#pragma once
// Where a missing panel lies, and how large it is. A reflection fixes one point of the
// surface and its normal (image-source geometry, unexplained_reflections.h), not its
// extent. A square centred on that point and sized by the fit pairs has about the right
// area but lies in the wrong place: in the planted test it does not reach the point a
// held-out pair hears, 1.14 m away. So the two are separated here. The fit
// pairs' geometry bounds where the panel may lie: it holds the points that saw it, grows
// in its plane up to a prior size and the room's bounds, and is cut back where a fit pair
// denies it (where it would give that pair a strong reflection its measurement lacks, or
// stand between its source and receiver). Its area, which the decay times do measure (a
// wood panel's two faces add absorption), is fitted; the panel of that area goes to the
// middle of what the bounds allow, the placement furthest from being wrong when nothing
// else says where it is.
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/evaluation/reflection_matching.h"

namespace room_reverb::core {

// The panel's plane: its reflecting face through `origin`, `normal` towards the pairs that
// saw it, `u` and `v` unit axes in the plane (u horizontal).
struct PanelPlane {
  Eigen::Vector3d origin, normal, u, v;
};

// A rectangle in the plane, in metres along u and v from the origin.
struct PanelExtent {
  double u_min = 0.0, u_max = 0.0, v_min = 0.0, v_max = 0.0;
  double width() const { return u_max - u_min; }
  double height() const { return v_max - v_min; }
};

// A fit pair, its measured reflections (relative to its direct sound, all levels) and
// the model's specular paths for it (paths.front() the direct sound).
struct PanelWitness {
  MeasurementPair pair;
  std::vector<RelativeReflection> reflections;
  std::vector<SpecularPath> paths;
};

// What a witness says about one point of the plane: its panel reflection point where that
// reflection would be strong (kStrongReflectionLatestS, kStrongReflectionLevelDb; by
// geometric spreading alone, so a little louder than a real panel's), confirmed when a
// measured reflection matches it that no model path explains, denied when none matches;
// or, denied, where its direct sound crosses the plane.
struct WitnessPoint {
  Eigen::Vector2d at;  // in-plane u, v (m)
  bool confirmed = false;
};
std::optional<WitnessPoint> witnessPoint(const PanelPlane& plane, const PanelWitness& witness, double speed_of_sound_m_s);

// Where the panel may lie: `support` (the points that saw it, plus the witnesses'
// confirmed points, 0.25 m round each) and `allowed`, the largest rectangle no more than
// kMaxPanelHalfM from the origin along either axis, inside the room, that holds the support
// and no point a witness denies. Denials are resolved nearest first, each by the one cut
// (of the four sides) that keeps the most area; a denial inside the support is overruled.
struct PanelBounds {
  PanelExtent support, allowed;
};
PanelBounds panelBounds(const PanelPlane& plane, const std::vector<Eigen::Vector3d>& support,
                        const std::vector<PanelWitness>& witnesses, const AcousticScene& scene,
                        double speed_of_sound_m_s);

// A panel about `side_m` square (no smaller than the support, no larger than allowed)
// centred in the allowed rectangle as far as holding the support lets it.
PanelExtent placePanel(const PanelBounds& bounds, double side_m);

// A panel is at most 2.5 m across unless the room stops it first: the size of a
// whiteboard, a partition or a glazed wall section, and the prior that one reflection
// cannot replace.
constexpr double kMaxPanelHalfM = 1.25;

}  // namespace room_reverb::core
