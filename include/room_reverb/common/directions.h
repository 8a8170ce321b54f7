#pragma once
// Directions in the room frame (DESIGN.md: x forward, y left, z up; azimuth
// counter-clockwise from +x, elevation up from the horizontal plane).
#include <Eigen/Core>
#include <cmath>

namespace room_reverb::core {

inline Eigen::Vector3d unitVectorFromAngles(double azimuth_rad, double elevation_rad) {
  return {std::cos(elevation_rad) * std::cos(azimuth_rad), std::cos(elevation_rad) * std::sin(azimuth_rad),
          std::sin(elevation_rad)};
}

}  // namespace room_reverb::core
