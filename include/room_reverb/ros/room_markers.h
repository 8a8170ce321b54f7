#pragma once
// The room model drawn for rviz: the box's faces as thin slabs and the objects as cuboids,
// each in a colour of its material's look (the capture textures' families: brick red,
// wood brown, carpet blue-grey...), and a text label per face and object giving its name,
// material and confidence.
#include <visualization_msgs/MarkerArray.h>

#include <string>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::ros_bridge {

// An ADD marker of `type` with an identity pose: what every marker here starts from.
visualization_msgs::Marker baseMarker(const std::string& frame, const ::ros::Time& stamp, const std::string& ns, int id,
                                      int type);

// Markers in `frame` (the model's frame, "room"). The first marker deletes all earlier
// ones, so a rebuilt room with fewer objects leaves nothing stale. Namespaces: surfaces,
// objects, labels.
visualization_msgs::MarkerArray roomMarkers(const core::RoomModel& model, const std::string& frame,
                                            const ::ros::Time& stamp);

}  // namespace room_reverb::ros_bridge
