#pragma once
// Three orthogonal vanishing directions from the great circles of line segments: RANSAC
// over minimal samples, then least squares (see vision/manhattan_from_image.h for the
// method and its references).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "sphere_line_segments.h"

namespace room_reverb::core::vision_detail {

struct VanishingDirections {
  Eigen::Matrix3d directions = Eigen::Matrix3d::Identity();  // columns: unit, orthogonal, in no order, signs arbitrary
  std::array<int, 3> inliers{};              // segments per column
  std::array<double, 3> inlier_length_rad{};  // their total length per column
  double rms_residual_rad = 0.0;  // of the inliers' n . v
};

// Segments whose great circle passes within inlier_rad of a direction are its inliers.
// With known_up (unit), column 2 is that direction and only the rotation about it is
// searched. At least 3 segments; the same seed gives the same result.
VanishingDirections fitVanishingDirections(const std::vector<SphereSegment>& segments, double inlier_rad,
                                           int ransac_iterations, std::uint64_t seed,
                                           const std::optional<Eigen::Vector3d>& known_up);

}  // namespace room_reverb::core::vision_detail
