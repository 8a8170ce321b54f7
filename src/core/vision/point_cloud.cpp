#include "room_reverb/vision/point_cloud.h"

#include <cstdint>
#include <cstring>
#include <fstream>

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

void savePointCloudPcd(const std::string& path, const PointCloud& cloud) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path + ": cannot write the point cloud");
  const std::size_t n = cloud.points.size();
  out << "# .PCD v0.7 - Point Cloud Data file format (room_reverb, frame " << cloud.frame << ")\n"
      << "VERSION 0.7\nFIELDS x y z rgb label\nSIZE 4 4 4 4 4\nTYPE F F F F U\nCOUNT 1 1 1 1 1\n"
      << "WIDTH " << n << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n << "\nDATA binary\n";
  std::vector<char> record(20);
  for (const CloudPoint& point : cloud.points) {
    // PCL keeps rgb as the bytes of 0x00RRGGBB stored in a float field.
    const std::uint32_t rgb = (std::uint32_t{point.r} << 16) | (std::uint32_t{point.g} << 8) | point.b;
    const std::uint32_t label = point.hint;
    std::memcpy(record.data(), point.p.data(), 12);
    std::memcpy(record.data() + 12, &rgb, 4);
    std::memcpy(record.data() + 16, &label, 4);
    out.write(record.data(), static_cast<std::streamsize>(record.size()));
  }
  if (!out) throw InputError(path + ": writing the point cloud failed");
}

}  // namespace room_reverb::core
