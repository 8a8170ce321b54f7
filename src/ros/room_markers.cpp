#include "room_reverb/ros/room_markers.h"

#include <array>
#include <cmath>
#include <cstdio>

#include "room_reverb/vision/texture_family.h"

namespace room_reverb::ros_bridge {

namespace {

using visualization_msgs::Marker;

constexpr double kSlabThickness = 0.02;  // [m] faces drawn as slabs this thick

// Display colours (RGB, 0..1) close to the mean colour of each family's capture texture,
// so that the markers look like the room; unknown materials are grey.
std::array<float, 3> materialColor(const std::string& material) {
  if (material.empty()) return {0.6f, 0.6f, 0.6f};
  using F = core::TextureFamily;
  switch (core::textureFamilyFor(material).family) {
    case F::kPlaster: return {0.92f, 0.90f, 0.84f};
    case F::kBrick: return {0.66f, 0.30f, 0.22f};
    case F::kWood: return {0.55f, 0.36f, 0.20f};
    case F::kCarpet: return {0.40f, 0.46f, 0.56f};
    case F::kTiles: return {0.90f, 0.92f, 0.93f};
    case F::kGlass: return {0.20f, 0.45f, 0.48f};
    case F::kFabric: return {0.75f, 0.15f, 0.15f};
    case F::kConcrete: return {0.55f, 0.55f, 0.55f};
    case F::kMetal: return {0.70f, 0.75f, 0.80f};
    case F::kFoam: return {0.22f, 0.22f, 0.24f};
    case F::kNatural: return {0.40f, 0.48f, 0.25f};
    case F::kOpening: return {0.05f, 0.05f, 0.05f};
  }
  return {0.6f, 0.6f, 0.6f};
}

void setColor(Marker& m, const std::string& material, float alpha) {
  const auto rgb = materialColor(material);
  m.color.r = rgb[0];
  m.color.g = rgb[1];
  m.color.b = rgb[2];
  m.color.a = alpha;
}

std::string labelText(const std::string& name, const std::string& material, double confidence) {
  char conf[32];
  std::snprintf(conf, sizeof(conf), "%.2f", confidence);
  return name + "\n" + (material.empty() ? std::string("?") : material) + " (" + conf + ")";
}

Marker textMarker(const std::string& frame, const ::ros::Time& stamp, int id, const Eigen::Vector3d& at,
                  const std::string& text) {
  Marker m = baseMarker(frame, stamp, "labels", id, Marker::TEXT_VIEW_FACING);
  m.pose.position.x = at.x();
  m.pose.position.y = at.y();
  m.pose.position.z = at.z();
  m.scale.z = 0.15;  // text height [m]
  m.color.r = m.color.g = m.color.b = 1.0f;
  m.color.a = 1.0f;
  m.text = text;
  return m;
}

// Centre and size of face k's slab (kRoomSurfaceNames order), just outside the room.
void faceSlab(const Eigen::Vector3d& size, int k, Eigen::Vector3d& centre, Eigen::Vector3d& extent) {
  centre = 0.5 * size;
  extent = size;
  const int axis = k < 2 ? 2 : (k < 4 ? 0 : 1);
  const bool at_max = (k % 2) == 1;
  centre[axis] = at_max ? size[axis] + 0.5 * kSlabThickness : -0.5 * kSlabThickness;
  extent[axis] = kSlabThickness;
}

}  // namespace

Marker baseMarker(const std::string& frame, const ::ros::Time& stamp, const std::string& ns, int id, int type) {
  Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = Marker::ADD;
  m.pose.orientation.w = 1.0;
  return m;
}

visualization_msgs::MarkerArray roomMarkers(const core::RoomModel& model, const std::string& frame,
                                            const ::ros::Time& stamp) {
  visualization_msgs::MarkerArray array;
  Marker clear;
  clear.header.frame_id = frame;
  clear.header.stamp = stamp;
  clear.action = Marker::DELETEALL;
  array.markers.push_back(clear);

  int label_id = 0;
  for (int k = 0; k < 6; ++k) {
    const std::string name = core::kRoomSurfaceNames[static_cast<std::size_t>(k)];
    const auto it = model.surfaces.find(name);
    if (it == model.surfaces.end()) continue;  // the ceiling of an open room
    Eigen::Vector3d centre, extent;
    faceSlab(model.size_m, k, centre, extent);
    Marker m = baseMarker(frame, stamp, "surfaces", k, Marker::CUBE);
    m.pose.position.x = centre.x();
    m.pose.position.y = centre.y();
    m.pose.position.z = centre.z();
    m.scale.x = extent.x();
    m.scale.y = extent.y();
    m.scale.z = extent.z();
    // The floor opaque (a translucent floor is drawn over the objects standing on it), walls
    // see-through, the ceiling faint: the inside stays visible.
    setColor(m, it->second.material, k == 0 ? 1.0f : (k == 1 ? 0.15f : 0.35f));
    array.markers.push_back(m);
    Eigen::Vector3d text_at = centre;
    if (k >= 2) text_at.z() = 0.75 * model.size_m.z();
    array.markers.push_back(
        textMarker(frame, stamp, label_id++, text_at, labelText(name, it->second.material, it->second.confidence)));
  }
  for (std::size_t i = 0; i < model.objects.size(); ++i) {
    const core::CuboidObject& object = model.objects[i];
    Marker m = baseMarker(frame, stamp, "objects", static_cast<int>(i), Marker::CUBE);
    m.pose.position.x = object.center_m.x();
    m.pose.position.y = object.center_m.y();
    m.pose.position.z = object.center_m.z();
    m.pose.orientation.z = std::sin(0.5 * object.yaw_rad);
    m.pose.orientation.w = std::cos(0.5 * object.yaw_rad);
    m.scale.x = object.size_m.x();
    m.scale.y = object.size_m.y();
    m.scale.z = object.size_m.z();
    setColor(m, object.material, 0.85f);
    array.markers.push_back(m);
    const Eigen::Vector3d above = object.center_m + Eigen::Vector3d(0.0, 0.0, 0.5 * object.size_m.z() + 0.15);
    array.markers.push_back(textMarker(frame, stamp, label_id++, above,
                                       labelText(object.label, object.material, object.confidence)));
  }
  return array;
}

}  // namespace room_reverb::ros_bridge
