#pragma once
// Levelling a stereo capture and turning it to the room's axes without breaking the
// stereo: what capture_ingest applies to the images, and what it leaves to the cloud.
//
// Why the rotation is split. The rig's two cameras sit on its z axis (the baseline), and
// vertical-baseline stereo (vision/spherical_stereo.h) needs that baseline on the images'
// polar axis: then a point's two images share a column. The baseline is fixed in the rig,
// so if the rig is tilted by t and the images are rotated all the way to gravity, the
// baseline leaves the pole by t; a point at range r then moves sideways between the images
// by about b sin(t) / r radians (t = 2 deg, b = 0.2 m, r = 1 m: 0.4 deg, 2.3 px at 2048 px),
// which matching along columns cannot follow, and the disparity along the column is
// biased as well. A tripod with a bubble level keeps t near a degree, not at zero, so the
// images are never rotated off the baseline. The rotation camera -> level room axes is
// split (swing-twist) into
//
//   camera_to_level = tilt * image_rotation
//
//  - image_rotation: about the camera's z (the baseline) by yaw, the "twist". Both images
//    are rotated by it (rotateEquirect, vision/equirect_rotation.h). It only turns
//    azimuth, so the baseline stays on the pole and the stereo works exactly as on the raw
//    images; their frame, the "aligned rig" frame, is the rig turned about its z to face
//    the room's walls (exactly so for an upright rig).
//  - tilt: the rest, a rotation about a horizontal axis by the angle between the rig's z
//    and up, the "swing". It is not applied to the images but published with them; the
//    points of the stereo cloud (in the aligned rig frame) are rotated by it, p_level =
//    tilt * p, before the room fit (vision/room_layout.h), which wants a level cloud.
//
// Nothing here needs the tilt to be small; only naming the room's axes from an image
// (vision/manhattan_from_image.h) needs the rig within 45 degrees of upright.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace room_reverb::core {

struct ImageLeveling {
  Eigen::Matrix3d image_rotation = Eigen::Matrix3d::Identity();  // camera -> aligned rig: about z by yaw_rad
  Eigen::Matrix3d tilt = Eigen::Matrix3d::Identity();            // aligned rig -> level: about a horizontal axis
  double yaw_rad = 0.0;   // in [-pi, pi]
  double tilt_rad = 0.0;  // in [0, pi]: the angle between the camera's z and up

  Eigen::Matrix3d cameraToLevel() const { return tilt * image_rotation; }
};

// The split of a rotation camera -> level frame (e.g. ManhattanImageEstimate::
// camera_to_manhattan). A camera upside down (tilt of pi) has no unique split: the yaw is
// taken as 0. InputError unless the matrix is a rotation (as in rotateEquirect).
ImageLeveling splitLeveling(const Eigen::Matrix3d& camera_to_level);

// Up (against gravity) in the camera frame, from an IMU's orientation camera -> world
// whose world z points up (gravity along world -z). For ManhattanImageOptions::known_up.
// InputError for a quaternion that is not finite or far from unit length (|norm - 1| >
// 1e-3; nearer ones are normalised).
Eigen::Vector3d cameraUpFromImu(const Eigen::Quaterniond& camera_to_world);

// The levelling an IMU gives: the tilt that brings the camera's z to up, and no yaw (an
// IMU's heading is magnetic north or arbitrary, not the room's walls: the yaw comes from
// the image, estimateManhattanFrame with known_up, or from the cloud). Use splitLeveling on
// the IMU's rotation instead when its world frame is the room's.
ImageLeveling levelingFromImu(const Eigen::Quaterniond& camera_to_world);

}  // namespace room_reverb::core
