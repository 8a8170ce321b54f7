#include "room_reverb/ros/parameters.h"

#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {

namespace {

// ~name into `value` when set; a value of another type (a string where a number belongs, a
// number where a list does) stops the node rather than silently falling back.
template <typename T>
void readTyped(const ::ros::NodeHandle& nh, const std::string& name, T& value, const char* type) {
  if (!nh.hasParam(name)) return;
  if (!nh.getParam(name, value)) throw core::InputError("parameter ~" + name + " must be " + type);
}

}  // namespace

void readTypedParam(const ::ros::NodeHandle& nh, const std::string& name, bool& value) {
  readTyped(nh, name, value, "true or false");
}
void readTypedParam(const ::ros::NodeHandle& nh, const std::string& name, int& value) {
  readTyped(nh, name, value, "an integer");
}
void readTypedParam(const ::ros::NodeHandle& nh, const std::string& name, double& value) {
  readTyped(nh, name, value, "a number");
}
void readTypedParam(const ::ros::NodeHandle& nh, const std::string& name, std::string& value) {
  readTyped(nh, name, value, "a string");
}

int positiveIntParam(::ros::NodeHandle& nh, const std::string& name, int fallback) {
  int value = fallback;
  readTyped(nh, name, value, "an integer");
  if (value <= 0) throw core::InputError("parameter ~" + name + " must be positive (got " + std::to_string(value) + ")");
  return value;
}

double positiveDoubleParam(::ros::NodeHandle& nh, const std::string& name, double fallback) {
  double value = fallback;
  readTyped(nh, name, value, "a number");
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw core::InputError("parameter ~" + name + " must be positive and finite (got " + std::to_string(value) + ")");
  }
  return value;
}

std::vector<std::string> stringListParam(::ros::NodeHandle& nh, const std::string& name) {
  std::vector<std::string> value;
  readTyped(nh, name, value, "a list of strings");
  return value;
}

}  // namespace room_reverb::ros_bridge
