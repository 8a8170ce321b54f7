#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/vision/dual_fisheye.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Nominal mounts, columns = the lens's x (image right), y (image down), z (axis) in the
// camera frame.
Eigen::Matrix3d nominalMount(FisheyeSide side) {
  Eigen::Matrix3d m;
  if (side == FisheyeSide::kFront) {
    m << 0, 0, 1,
        -1, 0, 0,
         0, -1, 0;
  } else {
    m << 0, 0, -1,
         1, 0, 0,
         0, -1, 0;
  }
  return m;
}

double halfFov(const FisheyeLens& lens) { return 0.5 * lens.fov_deg * kDeg; }

}  // namespace

DualFisheyeCalibration idealDualFisheye(int size_px) {
  DualFisheyeCalibration calibration;
  calibration.size_px = size_px;
  for (FisheyeLens* lens : {&calibration.front, &calibration.back}) {
    lens->center_px = Eigen::Vector2d::Constant(0.5 * size_px);
    // A little inside the half, as on a real sensor, so a decentred circle still fits.
    lens->radius_px = 0.48 * size_px;
    lens->fov_deg = 190.0;
    lens->rotation_rpy_deg.setZero();
  }
  return calibration;
}

DualFisheyeCalibration scaledDualFisheye(const DualFisheyeCalibration& calibration, int size_px) {
  DualFisheyeCalibration scaled = calibration;
  const double k = static_cast<double>(size_px) / calibration.size_px;
  scaled.size_px = size_px;
  for (FisheyeLens* lens : {&scaled.front, &scaled.back}) {
    lens->center_px *= k;
    lens->radius_px *= k;
  }
  return scaled;
}

void validateDualFisheyeCalibration(const DualFisheyeCalibration& calibration, const std::string& source) {
  auto fail = [&](const std::string& key, const std::string& message) {
    throw InputError(source + ": " + key + ": " + message);
  };
  if (calibration.size_px < 16) fail("size_px", "must be at least 16 pixels (got " + std::to_string(calibration.size_px) + ")");
  for (const FisheyeSide side : {FisheyeSide::kFront, FisheyeSide::kBack}) {
    const FisheyeLens& lens = calibration.lens(side);
    const std::string name = side == FisheyeSide::kFront ? "front" : "back";
    if (!lens.center_px.allFinite() || (lens.center_px.array() < 0.0).any() ||
        (lens.center_px.array() > calibration.size_px).any()) {
      std::ostringstream os;
      os << "must lie inside the lens's " << calibration.size_px << " x " << calibration.size_px << " half (got "
         << lens.center_px.transpose() << ")";
      fail(name + ".center_px", os.str());
    }
    if (!(lens.radius_px > 0.0) || !std::isfinite(lens.radius_px)) fail(name + ".radius_px", "must be a positive number of pixels");
    // Both lenses must see past 90° for the image circles to overlap and be stitched.
    if (!(lens.fov_deg > 180.0 && lens.fov_deg < 360.0)) {
      fail(name + ".fov_deg", "must be between 180 and 360 degrees (got " + std::to_string(lens.fov_deg) + ")");
    }
    if (!lens.rotation_rpy_deg.allFinite() || (lens.rotation_rpy_deg.array().abs() >= 10.0).any()) {
      fail(name + ".rotation_rpy_deg", "must be a small correction, each angle under 10 degrees");
    }
  }
}

Eigen::Matrix3d fisheyeLensToCamera(const FisheyeLens& lens, FisheyeSide side) {
  const Eigen::Vector3d& rpy = lens.rotation_rpy_deg;
  const Eigen::Matrix3d deviation = (Eigen::AngleAxisd(rpy.z() * kDeg, Eigen::Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(rpy.y() * kDeg, Eigen::Vector3d::UnitY()) *
                                     Eigen::AngleAxisd(rpy.x() * kDeg, Eigen::Vector3d::UnitX()))
                                        .toRotationMatrix();
  return deviation * nominalMount(side);
}

double fisheyeAngleFromAxis(const FisheyeLens& lens, FisheyeSide side, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = fisheyeLensToCamera(lens, side).transpose() * direction;
  return std::atan2(std::hypot(d.x(), d.y()), d.z());
}

std::optional<Eigen::Vector2d> fisheyeProject(const FisheyeLens& lens, FisheyeSide side, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = fisheyeLensToCamera(lens, side).transpose() * direction;
  const double sideways = std::hypot(d.x(), d.y());
  const double angle = std::atan2(sideways, d.z());
  if (angle > halfFov(lens)) return std::nullopt;
  const double r = lens.radius_px * angle / halfFov(lens);
  if (sideways == 0.0) return lens.center_px;  // on the axis
  return Eigen::Vector2d(lens.center_px.x() + r * d.x() / sideways, lens.center_px.y() + r * d.y() / sideways);
}

std::optional<Eigen::Vector3d> fisheyeUnproject(const FisheyeLens& lens, FisheyeSide side, const Eigen::Vector2d& pixel) {
  const Eigen::Vector2d offset = pixel - lens.center_px;
  const double r = offset.norm();
  if (r > lens.radius_px) return std::nullopt;
  const double angle = r / lens.radius_px * halfFov(lens);
  Eigen::Vector3d d(0.0, 0.0, std::cos(angle));
  if (r > 0.0) d.head<2>() = std::sin(angle) * offset / r;
  return fisheyeLensToCamera(lens, side) * d;
}

}  // namespace room_reverb::core
