#pragma once
// A walking listener drawn for rviz (binaural_renderer ~markers): the head and where it
// faces, the source, the image sources of the reflections heard there and their paths,
// lines from the source through each reflection point to the listener, coloured by what
// the reflection rests on and faded by its level.
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "room_reverb/rsao/listener_translation.h"

namespace room_reverb::ros_bridge {

// Markers in `frame` (the room frame). The first marker deletes the earlier ones, so paths
// that stop being heard leave nothing behind. Namespaces: listener (a sphere and an arrow
// along the head's x axis), source, image_sources (a sphere list), reflection_paths (a line
// list: green on the room model's planes, cyan completed from it, yellow unchecked, grey
// unmatched; opaque at the direct sound's level, fading to 0.15 at 40 dB below).
visualization_msgs::MarkerArray listenerMarkers(const core::ListenerTranslation& translation,
                                                const std::vector<core::ReflectionPath>& paths,
                                                const Eigen::Vector3d& listener_m, const Eigen::Quaterniond& head,
                                                const std::string& frame, const ::ros::Time& stamp);

}  // namespace room_reverb::ros_bridge
