#include "rotation_check.h"

#include <Eigen/LU>
#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core::vision_detail {

void requireRotation(const Eigen::Matrix3d& R, const std::string& who) {
  if (!R.allFinite() || (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
      std::abs(R.determinant() - 1.0) > 1e-6) {
    throw InputError(who + ": the matrix is not a rotation (it must be orthonormal with determinant +1)");
  }
}

}  // namespace room_reverb::core::vision_detail
