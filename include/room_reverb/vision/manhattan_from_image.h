#pragma once
// The room's axes seen in a 360-degree image: the Manhattan frame (Coughlan & Yuille,
// "Manhattan World", ICCV 1999) of a box-shaped room, i.e. the three orthogonal directions
// that most of its straight edges (wall corners, wall-floor and wall-ceiling edges, door
// and window frames, tiles, shelves) run along.
//
// Method:
//  1. Line segments in six overlapping perspective views of the panorama (LSD), each the
//     normal n of its great circle (src/core/vision/sphere_line_segments.h). A segment
//     whose 3D line runs along direction v has n . v = 0.
//  2. RANSAC over orthogonal triples from three segments (Bazin & Pollefeys, "3-line
//     RANSAC for orthogonal vanishing point detection", IROS 2012: v1 = n1 x n2, v2 =
//     v1 x n3, v3 = v1 x v2), scored by the length of the segments within twice
//     inlier_deg of one direction (a truncated quadratic, so a near miss counts less).
//  3. Refinement by weighted least squares over the rotation (Gauss-Newton on SO(3),
//     minimising sum length (n . v_k)^2 over each segment's nearest direction), with the
//     inliers chosen again at every step, first within twice inlier_deg, then within it.
//  4. Naming: z is the direction closest to the camera's z (up; so the rig must stand
//     within 45 degrees of upright), x the one of the other two closest to the camera's x,
//     so for a rig turned by less than 45 degrees the result is a small rotation. The
//     room's four horizontal axes are alike to lines, so the yaw is known modulo 90
//     degrees: it comes back within 45 degrees (exactly so for an upright rig).
//
// With the up direction known (an IMU: see vision/image_leveling.h) only the yaw is
// searched, about that axis.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

struct ManhattanImageOptions {
  // Perspective views of the segment search: field of view [deg] of each of the six
  // (over 90 so that neighbours overlap) and side [px]; 0 picks the side whose centre
  // resolution matches the panorama's.
  double view_fov_deg = 100.0;
  int view_size_px = 0;
  // The side picked by view_size_px = 0 is at most this (0: no cap). Views of 512 px from a
  // 2048 px panorama (where the picked side is 776) put the tilt of the bundled rooms,
  // rendered turned by 1.8-3.2 degrees, within 0.060 degrees (mean 0.032) against 0.056
  // (0.028) at full size, and the yaw within 0.049 (0.021) against 0.043 (0.013), in 45 %
  // of the time; at 388 px the tilt is within 0.090.
  int max_view_size_px = 512;
  double min_segment_deg = 1.5;   // shorter segments are dropped: their direction is too uncertain
  double inlier_deg = 1.0;        // largest angle between a segment's great circle and its vanishing direction
  int ransac_iterations = 3000;
  std::uint64_t seed = 1;         // RANSAC's samples
  // Up in the camera frame (unit, e.g. from an IMU): when set, z is this direction and only
  // the yaw about it is estimated.
  std::optional<Eigen::Vector3d> known_up;
  // No Manhattan structure (InputError) when: fewer than min_segments segments; less than
  // min_inlier_fraction of their total length on the three directions (random segments
  // put about 3 x sin(inlier_deg) there); or the second best supported direction with
  // less than min_second_axis_fraction of the length or fewer than min_axis_segments
  // segments. One direction alone does not fix the frame (the turn about it is free), and
  // lines that nearly all run one way are not a room: a blurred or painted panorama's
  // blobs are stretched into streaks through the poles, which look like vertical edges.
  // Measured: rendered rooms put 20 % or more on their second direction, noise and
  // blurred noise under 5 %.
  int min_segments = 40;
  double min_inlier_fraction = 0.3;
  double min_second_axis_fraction = 0.08;
  int min_axis_segments = 10;
};

// The images have straight edges, but too few of them run along three orthogonal
// directions to name the room's axes (plain walls, clutter, curtains, tile lines that
// dominate): a room the cloud can still level (vision/cloud_leveling.h). Fewer than
// min_segments segments at all (a black, blurred or noise image) is a plain InputError.
class ManhattanStructureError : public InputError {
 public:
  using InputError::InputError;
};

struct ManhattanImageEstimate {
  // Rotation camera -> Manhattan frame: its rows are the room's x, y, z axes in the camera
  // frame. A direction d seen by the camera runs along camera_to_manhattan * d in the room.
  Eigen::Matrix3d camera_to_manhattan = Eigen::Matrix3d::Identity();
  double yaw_rad = 0.0;   // the turn about the camera's z (ImageLeveling::yaw_rad), within about +-pi/4
  double tilt_rad = 0.0;  // angle between the camera's z and the room's z
  int segments = 0;                       // line segments found
  std::array<int, 3> axis_inliers{};      // segments on the x, y, z directions
  std::array<double, 3> axis_fraction{};  // their share of all segments' total length
  double inlier_fraction = 0.0;           // the sum of the three shares
  double rms_residual_deg = 0.0;          // angle between the inliers' great circles and their directions
};

// The Manhattan frame of one equirectangular image (8-bit, grey or BGR, 2:1, at least 256
// px wide), or of several taken with the same orientation (the rig's top and bottom
// cameras: vanishing directions lie at infinity, so the baseline does not matter and the
// segments are pooled). InputError for unusable images or options, or an image without
// Manhattan structure (see ManhattanImageOptions), with the numbers that fell short.
ManhattanImageEstimate estimateManhattanFrame(const cv::Mat& image, const ManhattanImageOptions& options = {});
ManhattanImageEstimate estimateManhattanFrame(const std::vector<cv::Mat>& images, const ManhattanImageOptions& options = {});
// The same for images whose cameras are turned against each other: image i's segments are
// turned by rotations[i] (its camera frame -> the frame the estimate is in; a rectified
// pair: identity for the top camera and the bottom camera's turn, PairRectification::
// bottom_rotation, for the bottom one), so the images need not be resampled first.
// InputError unless there is one rotation per image, each a rotation.
ManhattanImageEstimate estimateManhattanFrame(const std::vector<cv::Mat>& images,
                                              const std::vector<Eigen::Matrix3d>& rotations,
                                              const ManhattanImageOptions& options = {});

}  // namespace room_reverb::core
