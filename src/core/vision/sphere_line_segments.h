#pragma once
// Straight line segments of an equirectangular image, as great circles of the sphere.
//
// A straight 3D line is a curve in an equirectangular image but a straight line in any
// perspective view, so the panorama is resampled into six overlapping perspective views
// (a cube map with faces wider than 90 degrees, so that a segment crossing a face's edge
// is seen whole in a neighbour) and searched there with the Line Segment Detector (von
// Gioi, Jakubowicz, Morel & Randall, "LSD: a fast line segment detector with a false
// detection control", IPOL 2012), whose a-contrario test finds (almost) nothing in noise.
// Every segment and the camera centre span a plane: its normal is what vanishing-point
// estimation needs (a line through vanishing direction v has n . v = 0).
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace room_reverb::core::vision_detail {

struct SphereSegment {
  Eigen::Vector3d normal;  // unit normal of the segment's great circle, camera frame
  double length_rad;       // angle between its end points
};

// Segments of at least min_length_rad in 8-bit single-channel equirectangular images of
// one size, image by image and view by view. Each view spans view_fov_rad (< pi) over
// view_size_px pixels; its resampling map is worked out once for all the images (the
// map's trigonometry costs as much as the resampling). A segment lying in the overlap of
// two views may be found in both. One list per image.
std::vector<std::vector<SphereSegment>> detectSphereSegments(const std::vector<cv::Mat>& grey_equirects,
                                                             int view_size_px, double view_fov_rad,
                                                             double min_length_rad);

}  // namespace room_reverb::core::vision_detail
