#pragma once
// Conversions between the RoomModel message and the core's room model, and of positions
// in the room.
#include <geometry_msgs/Point.h>
#include <room_reverb/RoomModel.h>

#include <Eigen/Core>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::ros_bridge {

// Throws core::InputError for a message the core cannot use (wrong number of band values,
// a missing face material, a wrong frame, surface_confidence of the wrong length); the
// core's own checks (sizes, coefficient ranges) apply on top when the model is used.
core::RoomModel fromMessage(const room_reverb::RoomModel& msg);
room_reverb::RoomModel toMessage(const core::RoomModel& model);

geometry_msgs::Point toPoint(const Eigen::Vector3d& p);

}  // namespace room_reverb::ros_bridge
