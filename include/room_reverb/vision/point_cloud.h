#pragma once
// A plain point cloud for the visual route: what spherical stereo produces and the room
// layout fit consumes. No PCL types here, so the core's public headers stay PCL-free; a
// ROS node converts sensor_msgs/PointCloud2 to this at the edge.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace room_reverb::core {

// What a point is believed to lie on, if a segmenter says so. Only a hint: the layout fit
// uses it to keep furniture out of the plane estimates and planes out of the furniture
// clusters, never to override the geometry.
enum class SurfaceHint : std::uint16_t {
  unknown = 0,
  floor = 1,
  ceiling = 2,
  wall = 3,
  object = 4,  // furniture or anything else standing in the room
};

struct CloudPoint {
  Eigen::Vector3f p = Eigen::Vector3f::Zero();  // position [m] in the cloud's frame
  std::uint8_t r = 0, g = 0, b = 0;             // colour; all zero when the cloud has none
  std::uint16_t hint = 0;                       // a SurfaceHint value; others count as unknown
};

struct PointCloud {
  std::string frame = "rig";  // frame id of every point
  std::vector<CloudPoint> points;
  bool has_color = false;  // r, g, b are meaningful
};

// Throws InputError if the cloud is empty, has fewer than min_points points, or holds a
// non-finite coordinate (the message gives the first bad point's index).
void checkPointCloud(const PointCloud& cloud, std::size_t min_points);

// Writes the cloud as a binary PCD v0.7 file (PCL's format: fields x y z rgb label, rgb
// packed as PCL packs it, label = the SurfaceHint), readable by pcl_viewer and CloudCompare.
// InputError if the file cannot be written.
void savePointCloudPcd(const std::string& path, const PointCloud& cloud);

}  // namespace room_reverb::core
