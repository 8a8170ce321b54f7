#include "room_reverb/vision/image_leveling.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "room_reverb/common/error.h"
#include "rotation_check.h"

namespace room_reverb::core {

ImageLeveling splitLeveling(const Eigen::Matrix3d& camera_to_level) {
  const Eigen::Matrix3d& R = camera_to_level;
  vision_detail::requireRotation(R, "splitLeveling");
  // Swing-twist: for q = swing * twist with the twist about z and the swing's axis
  // horizontal, the twist is q's scalar and z parts, normalised.
  Eigen::Quaterniond q(R);
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double twist_norm = std::hypot(q.w(), q.z());
  ImageLeveling out;
  if (twist_norm > 1e-12) {
    const Eigen::Quaterniond twist(q.w() / twist_norm, 0.0, 0.0, q.z() / twist_norm);
    out.yaw_rad = 2.0 * std::atan2(twist.z(), twist.w());  // twist.w >= 0: in (-pi, pi]
    out.image_rotation = twist.toRotationMatrix();
  }
  out.tilt = R * out.image_rotation.transpose();
  out.tilt_rad = std::acos(std::clamp(R(2, 2), -1.0, 1.0));
  return out;
}

Eigen::Vector3d cameraUpFromImu(const Eigen::Quaterniond& camera_to_world) {
  const double norm = camera_to_world.norm();
  if (!camera_to_world.coeffs().allFinite() || std::abs(norm - 1.0) > 1e-3) {
    throw InputError("IMU orientation: the quaternion is not a unit quaternion (norm " + std::to_string(norm) + ")");
  }
  return camera_to_world.normalized().conjugate() * Eigen::Vector3d::UnitZ();
}

ImageLeveling levelingFromImu(const Eigen::Quaterniond& camera_to_world) {
  const Eigen::Vector3d up = cameraUpFromImu(camera_to_world);
  return splitLeveling(Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ()).toRotationMatrix());
}

}  // namespace room_reverb::core
