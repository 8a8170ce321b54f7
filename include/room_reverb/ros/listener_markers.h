#pragma once
// A walking listener drawn for rviz (binaural_renderer ~markers): the head and where it
// faces, the source, the image sources of the reflections heard there and their paths,
// lines from the source through each reflection point to the listener, coloured by what
// the reflection rests on and faded by its level. For both walkable routes: an RSAO moved
// in its room model (listener_translation.h) and a simulated room (simulated_walk.h).
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/acoustics/simulated_walk.h"
#include "room_reverb/rsao/listener_translation.h"

namespace room_reverb::ros_bridge {

// One path heard, as drawn.
struct DrawnPath {
  std::array<float, 3> rgb{1.0f, 1.0f, 1.0f};
  double level = 0.0;  // pressure, on a scale the paths of one drawing share
  bool direct = false;  // the direct sound: the level the others fade from
  std::optional<Eigen::Vector3d> image_source_m;  // none for the direct sound
  std::vector<Eigen::Vector3d> points;  // from the source (or the image) to the listener
};

// The RSAO route's paths heard (ListenerTranslation::heardPathsAt): green on the room
// model's planes, cyan completed from it, yellow unchecked, grey unmatched; the direct
// sound orange.
std::vector<DrawnPath> drawnPaths(const core::ListenerTranslation& translation,
                                  const std::vector<core::ReflectionPath>& paths);
// The simulated route's image-source paths at `listener_m` (SimulatedWalk::pathsAt, its
// InputErrors): the direct sound orange, first-order reflections green, later orders cyan;
// each level the paths' pressure gain, RMS over the octave bands.
std::vector<DrawnPath> drawnPaths(const core::SimulatedWalk& walk, const Eigen::Vector3d& listener_m);

// Markers in `frame` (the room frame). The first marker deletes the earlier ones, so paths
// that stop being heard leave nothing behind. Namespaces: listener (a sphere and an arrow
// along the head's x axis), source, image_sources (a sphere list), reflection_paths (a line
// list, opaque at the direct sound's level, fading to 0.15 at 40 dB below).
visualization_msgs::MarkerArray listenerMarkers(const Eigen::Vector3d& source_m, const std::vector<DrawnPath>& paths,
                                                const Eigen::Vector3d& listener_m, const Eigen::Quaterniond& head,
                                                const std::string& frame, const ::ros::Time& stamp);

}  // namespace room_reverb::ros_bridge
