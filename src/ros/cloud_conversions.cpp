#include "room_reverb/ros/cloud_conversions.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl_conversions/pcl_conversions.h>

#include <cmath>
#include <cstring>

#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {

namespace {

const sensor_msgs::PointField* findField(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  for (const auto& field : msg.fields) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

// Whether a 4-byte field lies inside the point; in 64 bits, as an offset near 2^32 would
// wrap past a 32-bit check and send the reads outside the message.
bool fieldFits(const sensor_msgs::PointField& field, std::uint32_t point_step) {
  return std::uint64_t{field.offset} + 4 <= point_step;
}

const sensor_msgs::PointField& requireFloatField(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  const sensor_msgs::PointField* field = findField(msg, name);
  if (field == nullptr || field->datatype != sensor_msgs::PointField::FLOAT32) {
    throw core::InputError("point cloud: needs a float32 field '" + name + "'");
  }
  if (!fieldFits(*field, msg.point_step)) throw core::InputError("point cloud: field '" + name + "' lies outside the point");
  return *field;
}

template <typename T>
T readAt(const std::uint8_t* point, std::uint32_t offset) {
  T value;
  std::memcpy(&value, point + offset, sizeof(T));
  return value;
}

}  // namespace

sensor_msgs::PointCloud2 cloudToMessage(const core::PointCloud& cloud, const std_msgs::Header& header) {
  pcl::PointCloud<pcl::PointXYZRGBL> pcl_cloud;
  pcl_cloud.reserve(cloud.points.size());
  for (const core::CloudPoint& point : cloud.points) {
    pcl::PointXYZRGBL p;
    p.x = point.p.x();
    p.y = point.p.y();
    p.z = point.p.z();
    p.r = point.r;
    p.g = point.g;
    p.b = point.b;
    p.a = 255;
    p.label = point.hint;
    pcl_cloud.push_back(p);
  }
  pcl_cloud.is_dense = true;
  sensor_msgs::PointCloud2 msg;
  pcl::toROSMsg(pcl_cloud, msg);
  msg.header = header;
  if (msg.header.frame_id.empty()) msg.header.frame_id = cloud.frame;
  return msg;
}

namespace {

struct XyzFields {
  sensor_msgs::PointField x, y, z;
};

// The structural checks (sizes, x/y/z float fields inside the point, byte order), and the
// coordinate fields they found.
XyzFields checkedXyzFields(const sensor_msgs::PointCloud2& msg) {
  const std::size_t count = static_cast<std::size_t>(msg.width) * msg.height;
  if (count > 0 && (msg.row_step < static_cast<std::size_t>(msg.width) * msg.point_step ||
                    msg.data.size() < static_cast<std::size_t>(msg.row_step) * msg.height)) {
    throw core::InputError("point cloud: " + std::to_string(msg.data.size()) + " bytes cannot hold " +
                           std::to_string(msg.height) + " rows of " + std::to_string(msg.width) + " points of " +
                           std::to_string(msg.point_step) + " bytes");
  }
  XyzFields fields{requireFloatField(msg, "x"), requireFloatField(msg, "y"), requireFloatField(msg, "z")};
  if (msg.is_bigendian) throw core::InputError("point cloud: big-endian data is not supported");
  return fields;
}

}  // namespace

void checkCloudMessage(const sensor_msgs::PointCloud2& msg) { checkedXyzFields(msg); }

core::PointCloud cloudFromMessage(const sensor_msgs::PointCloud2& msg) {
  const auto [fx, fy, fz] = checkedXyzFields(msg);
  const std::size_t count = static_cast<std::size_t>(msg.width) * msg.height;
  const sensor_msgs::PointField* rgb = findField(msg, "rgb");
  if (rgb == nullptr) rgb = findField(msg, "rgba");
  if (rgb != nullptr && !fieldFits(*rgb, msg.point_step)) rgb = nullptr;
  const sensor_msgs::PointField* label = findField(msg, "label");
  if (label != nullptr && (label->datatype != sensor_msgs::PointField::UINT32 || !fieldFits(*label, msg.point_step))) {
    label = nullptr;
  }

  core::PointCloud cloud;
  cloud.frame = msg.header.frame_id;
  cloud.has_color = rgb != nullptr;
  cloud.points.reserve(count);
  for (std::uint32_t row = 0; row < msg.height; ++row) {
    for (std::uint32_t col = 0; col < msg.width; ++col) {
      const std::uint8_t* point = msg.data.data() + static_cast<std::size_t>(row) * msg.row_step +
                                  static_cast<std::size_t>(col) * msg.point_step;
      core::CloudPoint p;
      p.p = {readAt<float>(point, fx.offset), readAt<float>(point, fy.offset), readAt<float>(point, fz.offset)};
      if (!p.p.allFinite()) continue;
      if (rgb != nullptr) {
        // PCL packs rgb as 0x00RRGGBB in a float's bytes (little-endian: b, g, r, a).
        const auto packed = readAt<std::uint32_t>(point, rgb->offset);
        p.r = static_cast<std::uint8_t>((packed >> 16) & 0xff);
        p.g = static_cast<std::uint8_t>((packed >> 8) & 0xff);
        p.b = static_cast<std::uint8_t>(packed & 0xff);
      }
      if (label != nullptr) {
        const auto value = readAt<std::uint32_t>(point, label->offset);
        p.hint = value <= 4 ? static_cast<std::uint16_t>(value) : 0;
      }
      cloud.points.push_back(p);
    }
  }
  return cloud;
}

}  // namespace room_reverb::ros_bridge
