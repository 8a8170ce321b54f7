#pragma once
// Reading node parameters loudly: a bad value stops the node with a message naming it.
#include <ros/ros.h>

#include <string>
#include <vector>

namespace room_reverb::ros_bridge {

// ~name as an int, `fallback` when unset; core::InputError unless it is a positive integer.
int positiveIntParam(::ros::NodeHandle& nh, const std::string& name, int fallback);
// ~name as a double (an integer is accepted), `fallback` when unset; core::InputError
// unless it is a positive, finite number.
double positiveDoubleParam(::ros::NodeHandle& nh, const std::string& name, double fallback);
// ~name as a list of strings, empty when unset; core::InputError when it is set to anything else.
std::vector<std::string> stringListParam(::ros::NodeHandle& nh, const std::string& name);

}  // namespace room_reverb::ros_bridge
