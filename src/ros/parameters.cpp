#include "room_reverb/ros/parameters.h"

#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {

int positiveIntParam(::ros::NodeHandle& nh, const std::string& name, int fallback) {
  int value = fallback;
  nh.param(name, value, fallback);
  if (value <= 0) throw core::InputError("parameter ~" + name + " must be positive (got " + std::to_string(value) + ")");
  return value;
}

double positiveDoubleParam(::ros::NodeHandle& nh, const std::string& name, double fallback) {
  double value = fallback;
  nh.param(name, value, fallback);
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw core::InputError("parameter ~" + name + " must be positive and finite (got " + std::to_string(value) + ")");
  }
  return value;
}

}  // namespace room_reverb::ros_bridge
