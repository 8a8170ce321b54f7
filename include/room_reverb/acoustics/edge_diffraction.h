#pragma once
// The direct sound bent around a piece of furniture: a listener behind a cabinet hears the
// source weaker and duller, not silent. One cuboid object (cuboid.h), the shortest way
// around it over one edge or across a face over two, and the barrier loss of Kurze and
// Anderson (1971) at that way's path difference, the form behind ISO 9613-2's screening
// term (for two edges the total path difference, as ISO 9613-2 counts it, without its
// thickness term). Several objects in a row, transmission through an object and the
// diffraction of reflections are not modelled.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "room_reverb/acoustics/cuboid.h"
#include "room_reverb/acoustics/material.h"

namespace room_reverb::core {

// A path from a source to a listener over one edge of an object, or across one face over
// two of its parallel edges.
struct EdgeDetour {
  std::vector<Eigen::Vector3d> turns;  // where it turns, on the edges, from the source's side (room frame)
  double length_m = 0.0;           // |source - edge_point| + |edge_point - listener|
  double path_difference_m = 0.0;  // length_m - |source - listener|, >= 0
  bool shadowed = false;           // the straight line runs through the object
};

// Whether the segment from `a` to `b` runs through the object's interior (touching a face
// or an edge does not count).
bool segmentCrossesCuboid(const CuboidObject& object, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// The shortest path from `source` to `listener` around the object, over one of its twelve
// edges or across one face over two opposite edges (an object thicker than its clearance
// from the line of sight), whose legs stay out of its interior: for a listener in the
// object's shadow the way the sound bends around it; for one in view, the edge nearest the
// line of sight (how close the listener is to the shadow). None for a degenerate object or
// points inside it.
std::optional<EdgeDetour> shortestEdgeDetour(const CuboidObject& object, const Eigen::Vector3d& source,
                                             const Eigen::Vector3d& listener);

// Kurze and Anderson's single-edge loss in dB for the Fresnel number N = 2 delta / lambda
// (delta the path difference): 5 + 20 log10(sqrt(2 pi N) / tanh sqrt(2 pi N)) in the shadow
// (N > 0), 5 dB at grazing, falling on the lit side as 5 + 20 log10(x / tan x),
// x = sqrt(2 pi |N|), to 0 at about N = -0.2; at most 20 dB (ISO 9613-2's cap for one edge).
double barrierLossDb(double fresnel_number);

// Per band (at `band_centres_hz`, the octaves' by default) the pressure gain the edge adds:
// in the shadow the loss at N = 2 delta f / c, on the lit side the loss at -N (1 well
// clear of the shadow).
OctaveBandValues edgeDiffractionGains(const EdgeDetour& detour, double speed_of_sound_m_s,
                                      const OctaveBandValues& band_centres_hz = octaveCentresHz());

// The direct sound from `source` to `listener` among `objects`, as both routes hear it
// (the simulated route's image sources, the measured route's moved RSAO): blocked
// (`in_view` false), bent around the edge of the object that takes the least at 1 kHz
// whose way round no other object blocks; in view, weakened by the object whose shadow it
// passes nearest (the most at 1 kHz). None when it is blocked and no single edge clears
// it. The edge is chosen in octaves; `band_centres_hz` are where its gains are evaluated
// (a third-octave view's bands hear the same edge).
struct DirectSoundPast {
  std::optional<EdgeDetour> detour;  // the edge it bends around or passes; none: no object near its way
  OctaveBandValues gains{};          // per band, the pressure gain that edge adds (1 without one)
  bool bent = false;                 // it arrives around the edge, later and from its direction
};
std::optional<DirectSoundPast> directSoundPastObjects(const std::vector<CuboidObject>& objects,
                                                      const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                                                      bool in_view, double speed_of_sound_m_s,
                                                      const OctaveBandValues& band_centres_hz = octaveCentresHz());

}  // namespace room_reverb::core
