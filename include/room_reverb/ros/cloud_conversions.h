#pragma once
// sensor_msgs/PointCloud2 to and from the core's PointCloud (vision/point_cloud.h).
#include <sensor_msgs/PointCloud2.h>

#include "room_reverb/vision/point_cloud.h"

namespace room_reverb::ros_bridge {

// An XYZRGBL cloud built with PCL (pcl::PointXYZRGBL): x, y, z [m], the packed rgb, and
// label = the point's SurfaceHint (0 unknown, 1 floor, 2 ceiling, 3 wall, 4 object). The
// message is unordered (height 1), dense, in the cloud's frame unless header.frame_id is set.
sensor_msgs::PointCloud2 cloudToMessage(const core::PointCloud& cloud, const std_msgs::Header& header);

// Any PointCloud2 with float32 x, y, z; rgb (or rgba) and label are read when present.
// Points with a non-finite coordinate (organised clouds mark holes with NaN) are skipped.
// core::InputError for a cloud without float32 x/y/z fields or with a data size that does
// not match its width, height and point step.
core::PointCloud cloudFromMessage(const sensor_msgs::PointCloud2& msg);
// The structural checks of cloudFromMessage (sizes, x/y/z float fields inside the point,
// byte order) without the conversion: for a cloud that is kept to be converted later.
void checkCloudMessage(const sensor_msgs::PointCloud2& msg);

}  // namespace room_reverb::ros_bridge
