#include "room_reverb/ros/room_conversions.h"

#include <algorithm>
#include <array>
#include <string>

#include "room_reverb/acoustics/relief_scattering.h"
#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {
namespace {

// The message's face fields in the order of core::kRoomSurfaceNames (const or not).
template <class Message>
auto faceMaterials(Message& msg) {
  return std::array{&msg.floor_material, &msg.ceiling_material, &msg.wall_x_min_material,
                    &msg.wall_x_max_material, &msg.wall_y_min_material, &msg.wall_y_max_material};
}

core::OctaveBandValues bandValues(const std::vector<double>& values, const std::string& key) {
  if (values.size() != core::kOctaveBandCount) {
    throw core::InputError(key + ": needs " + std::to_string(core::kOctaveBandCount) +
                           " values (octaves 63 Hz - 16 kHz), got " + std::to_string(values.size()));
  }
  core::OctaveBandValues out{};
  std::copy(values.begin(), values.end(), out.begin());
  return out;
}

}  // namespace

core::RoomModel fromMessage(const room_reverb::RoomModel& msg) {
  core::RoomModel model;
  if (!msg.header.frame_id.empty() && msg.header.frame_id != "room") {
    throw core::InputError("room model frame is '" + msg.header.frame_id + "'; the simulator works in the 'room' frame");
  }
  model.size_m = {msg.size.x, msg.size.y, msg.size.z};
  model.has_ceiling = msg.has_ceiling;
  if (!msg.surface_confidence.empty() && msg.surface_confidence.size() != 6) {
    throw core::InputError("surface_confidence needs 6 values (floor, ceiling, walls x-, x+, y-, y+) or none");
  }
  if (!msg.surface_relief_scattering.empty() && msg.surface_relief_scattering.size() != 6 * core::kOctaveBandCount) {
    throw core::InputError("surface_relief_scattering needs 6 x 9 values (face by face, 63 Hz-16 kHz) or none");
  }
  const auto faces = faceMaterials(msg);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (!msg.has_ceiling && i == 1 && faces[i]->empty()) continue;
    if (faces[i]->empty()) throw core::InputError(std::string(core::kRoomSurfaceNames[i]) + " has no material");
    core::SurfaceAssignment& surface = model.surfaces[core::kRoomSurfaceNames[i]];
    surface = {*faces[i], msg.surface_confidence.empty() ? 1.0 : msg.surface_confidence[i]};
    for (int b = 0; b < core::kOctaveBandCount && !msg.surface_relief_scattering.empty(); ++b) {
      surface.relief_scattering[b] = msg.surface_relief_scattering[i * core::kOctaveBandCount + b];
    }
  }
  for (std::size_t i = 0; i < msg.objects.size(); ++i) {
    const auto& o = msg.objects[i];
    core::CuboidObject object;
    object.label = o.label.empty() ? "object " + std::to_string(i) : o.label;
    object.material = o.material;
    object.center_m = {o.center.x, o.center.y, o.center.z};
    object.size_m = {o.size.x, o.size.y, o.size.z};
    object.yaw_rad = o.yaw;
    object.confidence = o.confidence;
    if (!o.relief_scattering.empty()) {
      object.relief_scattering = bandValues(o.relief_scattering, "object " + object.label + " relief_scattering");
    }
    model.objects.push_back(object);
  }
  for (const auto& m : msg.materials) {
    core::AcousticMaterial material;
    material.name = m.name;
    material.absorption = bandValues(m.absorption, "material " + m.name + " absorption");
    material.scattering = bandValues(m.scattering, "material " + m.name + " scattering");
    material.source = "RoomModel message";
    model.inline_materials.push_back(material);
  }
  if (msg.air_known) {
    model.air.enabled = msg.air_absorption;
    model.air.temperature_c = msg.temperature_c;
    model.air.humidity_percent = msg.humidity_percent;
  }
  return model;
}

room_reverb::RoomModel toMessage(const core::RoomModel& model) {
  room_reverb::RoomModel msg;
  msg.header.frame_id = model.frame;
  msg.size.x = model.size_m.x();
  msg.size.y = model.size_m.y();
  msg.size.z = model.size_m.z();
  msg.has_ceiling = model.has_ceiling;
  const auto faces = faceMaterials(msg);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const auto it = model.surfaces.find(core::kRoomSurfaceNames[i]);
    *faces[i] = it == model.surfaces.end() ? "" : it->second.material;
    msg.surface_confidence.push_back(it == model.surfaces.end() ? 0.0 : it->second.confidence);
  }
  const bool relief = std::any_of(model.surfaces.begin(), model.surfaces.end(),
                                  [](const auto& entry) { return core::hasRelief(entry.second.relief_scattering); });
  for (std::size_t i = 0; relief && i < faces.size(); ++i) {
    const auto it = model.surfaces.find(core::kRoomSurfaceNames[i]);
    for (int b = 0; b < core::kOctaveBandCount; ++b) {
      msg.surface_relief_scattering.push_back(it == model.surfaces.end() ? 0.0 : it->second.relief_scattering[b]);
    }
  }
  for (const auto& o : model.objects) {
    room_reverb::Cuboid c;
    c.label = o.label;
    c.material = o.material;
    c.center.x = o.center_m.x();
    c.center.y = o.center_m.y();
    c.center.z = o.center_m.z();
    c.size.x = o.size_m.x();
    c.size.y = o.size_m.y();
    c.size.z = o.size_m.z();
    c.yaw = o.yaw_rad;
    c.confidence = o.confidence;
    if (core::hasRelief(o.relief_scattering)) c.relief_scattering.assign(o.relief_scattering.begin(), o.relief_scattering.end());
    msg.objects.push_back(c);
  }
  for (const auto& m : model.inline_materials) {
    room_reverb::AcousticMaterial material;
    material.name = m.name;
    material.absorption.assign(m.absorption.begin(), m.absorption.end());
    material.scattering.assign(m.scattering.begin(), m.scattering.end());
    msg.materials.push_back(material);
  }
  msg.air_known = true;
  msg.air_absorption = model.air.enabled;
  msg.temperature_c = model.air.temperature_c;
  msg.humidity_percent = model.air.humidity_percent;
  return msg;
}

geometry_msgs::Point toPoint(const Eigen::Vector3d& p) {
  geometry_msgs::Point out;
  out.x = p.x();
  out.y = p.y();
  out.z = p.z();
  return out;
}

}  // namespace room_reverb::ros_bridge
