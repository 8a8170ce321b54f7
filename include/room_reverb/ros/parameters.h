#pragma once
// Reading node parameters loudly: a bad value stops the node with a message naming it.
#include <ros/ros.h>

#include <string>
#include <vector>

namespace room_reverb::ros_bridge {

// ~name into `value` as T (bool, int, double or std::string), `fallback` when unset;
// core::InputError when it is set to a value of another type (text where a number
// belongs, a number where a name does), which roscpp's own param() would silently
// replace by the fallback. The same arguments as NodeHandle::param.
void readTypedParam(const ::ros::NodeHandle& nh, const std::string& name, bool& value);
void readTypedParam(const ::ros::NodeHandle& nh, const std::string& name, int& value);
void readTypedParam(const ::ros::NodeHandle& nh, const std::string& name, double& value);
void readTypedParam(const ::ros::NodeHandle& nh, const std::string& name, std::string& value);

template <typename T, typename Fallback>
void typedParam(const ::ros::NodeHandle& nh, const std::string& name, T& value, const Fallback& fallback) {
  value = static_cast<T>(fallback);
  readTypedParam(nh, name, value);
}

// ~name as an int, `fallback` when unset; core::InputError unless it is a positive integer.
int positiveIntParam(::ros::NodeHandle& nh, const std::string& name, int fallback);
// ~name as a double (an integer is accepted), `fallback` when unset; core::InputError
// unless it is a positive, finite number.
double positiveDoubleParam(::ros::NodeHandle& nh, const std::string& name, double fallback);
// ~name as a list of strings, empty when unset; core::InputError when it is set to anything else.
std::vector<std::string> stringListParam(::ros::NodeHandle& nh, const std::string& name);

}  // namespace room_reverb::ros_bridge
