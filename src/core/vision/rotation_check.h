#pragma once
// The check every function taking a rotation matrix from a user makes.
#include <Eigen/Core>
#include <string>

namespace room_reverb::core::vision_detail {

// InputError "<who>: the matrix is not a rotation ..." unless R is finite, orthonormal and
// of determinant +1 (each within 1e-6).
void requireRotation(const Eigen::Matrix3d& R, const std::string& who);

}  // namespace room_reverb::core::vision_detail
