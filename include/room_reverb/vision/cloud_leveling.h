#pragma once
// Levelling a capture from its own point cloud, for rooms whose images show too few
// straight edges to name the room's axes (vision/manhattan_from_image.h): plain walls,
// clutter, curtains. The floor and the ceiling are the cloud's two largest horizontal
// layers; the tilt that makes them horizontal makes the histogram of the points' heights
// sharpest (the same measure sharpestPlanYaw uses for the walls' directions in plan).
#include <Eigen/Core>

#include "room_reverb/vision/point_cloud.h"

namespace room_reverb::core {

struct CloudLevelingOptions {
  double max_tilt_rad = 0.14;      // searched within this of upright (8 degrees: a hand-set tripod)
  double voxel_size_m = 0.05;      // one point per voxel, so area counts, not point density
  double bin_m = 0.01;             // height histogram resolution
  double max_range_m = 15.0;       // farther points are ignored (noisy, and few)
};

struct CloudLeveling {
  Eigen::Matrix3d tilt = Eigen::Matrix3d::Identity();  // p_level = tilt * p_rig (no yaw)
  double tilt_rad = 0.0;                                // the angle between the rig's z and up
  double sharpness_gain = 1.0;  // the best tilt's histogram sharpness over upright's
};

// InputError for a cloud of fewer than 1000 points or non-finite points, and for options
// out of range.
CloudLeveling levelFromCloud(const PointCloud& cloud, const CloudLevelingOptions& options = {});

}  // namespace room_reverb::core
