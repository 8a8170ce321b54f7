#pragma once
// The equirectangular image convention of the visual route (DESIGN.md: REP 103 frames,
// azimuth counter-clockwise from +x, elevation up from the horizontal).
//
// An equirectangular image of width W and height H = W / 2 maps pixel centres to
// directions in the camera's frame (x forward, y left, z up):
//   azimuth   phi   = pi - 2 pi (u + 0.5) / W     column u = 0 .. W-1: +180 deg at the left
//                                                 edge, 0 (straight ahead, +x) in the middle,
//                                                 -180 deg at the right edge (a panorama seen
//                                                 from inside: left in the image is left, +y)
//   elevation theta = pi / 2 - pi (v + 0.5) / H   row v = 0 .. H-1: the zenith at the top
// The seam (+-180 deg, behind the camera) is between the last and the first column.
// Continuous coordinates (u, v) use the same formulas without the 0.5, for pixel edges:
// u in [0, W), v in [0, H); pixel (i, j) covers [i, i+1) x [j, j+1).
#include <Eigen/Core>
#include <vector>

namespace room_reverb::core {

struct EquirectGeometry {
  int width = 0;   // W, columns
  int height = 0;  // H = W / 2, rows
};

// Unit direction of the centre of pixel (column u, row v).
Eigen::Vector3d equirectPixelDirection(const EquirectGeometry& g, double u, double v);
// Azimuth and elevation [rad] of a pixel centre.
double equirectAzimuth(const EquirectGeometry& g, double u);
double equirectElevation(const EquirectGeometry& g, double v);
// equirectPixelDirection's cosines and sines once per column and row, for work over every
// pixel of an image: the same directions to the bit, without two sines and cosines per pixel.
struct EquirectDirections {
  std::vector<double> cos_azimuth, sin_azimuth;      // per column u
  std::vector<double> cos_elevation, sin_elevation;  // per row v
  Eigen::Vector3d at(int u, int v) const {
    const auto cu = static_cast<std::size_t>(u), cv = static_cast<std::size_t>(v);
    return {cos_elevation[cv] * cos_azimuth[cu], cos_elevation[cv] * sin_azimuth[cu], sin_elevation[cv]};
  }
};
EquirectDirections equirectDirections(const EquirectGeometry& g);
// Continuous pixel coordinates (u in [0, W), v in [0, H)) of a direction (need not be unit);
// pixel centres are at integer + 0.5 of these, i.e. floor(u) is the column.
Eigen::Vector2d equirectCoordinates(const EquirectGeometry& g, const Eigen::Vector3d& direction);

}  // namespace room_reverb::core
