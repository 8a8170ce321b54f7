#include "room_reverb/vision/point_cloud.h"

#include "room_reverb/common/error.h"

namespace room_reverb::core {

void checkPointCloud(const PointCloud& cloud, std::size_t min_points) {
  if (cloud.points.empty()) throw InputError("point cloud: empty (no points to fit a room to)");
  if (cloud.points.size() < min_points) {
    throw InputError("point cloud: too few points (" + std::to_string(cloud.points.size()) + ", need at least " +
                     std::to_string(min_points) + "); capture a denser depth map");
  }
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    if (!cloud.points[i].p.allFinite()) {
      throw InputError("point cloud: point " + std::to_string(i) +
                       " is not finite; drop invalid depths (NaN/inf) before fitting");
    }
  }
}

}  // namespace room_reverb::core
