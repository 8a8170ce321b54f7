#include "room_reverb/vision/equirect.h"

#include <cmath>

namespace room_reverb::core {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

double equirectAzimuth(const EquirectGeometry& g, double u) {
  return kPi - 2.0 * kPi * (u + 0.5) / g.width;
}

double equirectElevation(const EquirectGeometry& g, double v) {
  return kPi / 2.0 - kPi * (v + 0.5) / g.height;
}

Eigen::Vector3d equirectPixelDirection(const EquirectGeometry& g, double u, double v) {
  const double phi = equirectAzimuth(g, u);
  const double theta = equirectElevation(g, v);
  return {std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), std::sin(theta)};
}

EquirectDirections equirectDirections(const EquirectGeometry& g) {
  EquirectDirections d;
  for (int u = 0; u < g.width; ++u) {
    const double phi = equirectAzimuth(g, u);
    d.cos_azimuth.push_back(std::cos(phi));
    d.sin_azimuth.push_back(std::sin(phi));
  }
  for (int v = 0; v < g.height; ++v) {
    const double theta = equirectElevation(g, v);
    d.cos_elevation.push_back(std::cos(theta));
    d.sin_elevation.push_back(std::sin(theta));
  }
  return d;
}

Eigen::Vector2d equirectCoordinates(const EquirectGeometry& g, const Eigen::Vector3d& direction) {
  const double phi = std::atan2(direction.y(), direction.x());
  const double theta = std::atan2(direction.z(), std::hypot(direction.x(), direction.y()));
  double u = (kPi - phi) / (2.0 * kPi) * g.width;
  if (u >= g.width) u -= g.width;
  if (u < 0.0) u += g.width;
  const double v = (kPi / 2.0 - theta) / kPi * g.height;
  return {u, v};
}

}  // namespace room_reverb::core
