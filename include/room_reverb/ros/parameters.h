#pragma once
// Reading node parameters loudly: a bad value stops the node with a message naming it.
#include <ros/ros.h>

#include <string>

namespace room_reverb::ros_bridge {

// ~name as an int, `fallback` when unset; core::InputError unless it is positive.
int positiveIntParam(::ros::NodeHandle& nh, const std::string& name, int fallback);
// ~name as a double, `fallback` when unset; core::InputError unless positive and finite.
double positiveDoubleParam(::ros::NodeHandle& nh, const std::string& name, double fallback);

}  // namespace room_reverb::ros_bridge
