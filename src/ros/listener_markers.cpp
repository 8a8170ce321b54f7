#include "room_reverb/ros/room_conversions.h"
#include "room_reverb/ros/listener_markers.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "room_reverb/ros/room_markers.h"

namespace room_reverb::ros_bridge {
namespace {

using visualization_msgs::Marker;

std_msgs::ColorRGBA rgba(const std::array<float, 3>& rgb, float alpha) {
  std_msgs::ColorRGBA c;
  c.r = rgb[0];
  c.g = rgb[1];
  c.b = rgb[2];
  c.a = alpha;
  return c;
}

std::array<float, 3> anchorColor(core::ReflectionAnchor anchor) {
  switch (anchor) {
    case core::ReflectionAnchor::kSource: return {1.0f, 0.55f, 0.0f};
    case core::ReflectionAnchor::kSurface: return {0.2f, 0.85f, 0.2f};
    case core::ReflectionAnchor::kModelled: return {0.1f, 0.8f, 0.9f};
    case core::ReflectionAnchor::kUnchecked: return {0.95f, 0.9f, 0.1f};
    case core::ReflectionAnchor::kUnmatched: return {0.6f, 0.6f, 0.6f};
  }
  return {1.0f, 1.0f, 1.0f};
}

}  // namespace

std::vector<DrawnPath> drawnPaths(const core::ListenerTranslation& translation,
                                  const std::vector<core::ReflectionPath>& paths) {
  std::vector<DrawnPath> drawn;
  for (const core::ReflectionPath& path : paths) {
    DrawnPath d;
    d.rgb = anchorColor(path.anchor);
    d.level = path.level;
    d.direct = path.anchor == core::ReflectionAnchor::kSource;
    if (!d.direct) d.image_source_m = translation.anchors()[path.index].image_source_m;
    d.points = path.points;
    drawn.push_back(std::move(d));
  }
  return drawn;
}

std::vector<DrawnPath> drawnPaths(const core::SimulatedWalk& walk, const Eigen::Vector3d& listener_m) {
  std::vector<DrawnPath> drawn;
  for (const core::SpecularPath& path : walk.pathsAt(listener_m)) {
    // pathsAt keeps only valid paths, so the points exist; a path that lost them to
    // rounding is left out of the drawing rather than drawn wrong.
    auto points = core::specularPathPoints(walk.scene(), walk.sourcePosition(), listener_m, path);
    if (!points) continue;
    DrawnPath d;
    d.direct = path.order == 0;
    d.rgb = anchorColor(d.direct ? core::ReflectionAnchor::kSource
                                 : (path.order == 1 ? core::ReflectionAnchor::kSurface : core::ReflectionAnchor::kModelled));
    double sum = 0.0;
    for (double g : path.pressure_gain) sum += g * g;
    d.level = std::sqrt(sum / static_cast<double>(path.pressure_gain.size()));
    if (!d.direct) d.image_source_m = path.image_position;
    d.points = std::move(*points);
    drawn.push_back(std::move(d));
  }
  return drawn;
}

visualization_msgs::MarkerArray listenerMarkers(const Eigen::Vector3d& source_m, const std::vector<DrawnPath>& paths,
                                                const Eigen::Vector3d& listener_m, const Eigen::Quaterniond& head,
                                                const std::string& frame, const ::ros::Time& stamp) {
  visualization_msgs::MarkerArray out;
  Marker clear = baseMarker(frame, stamp, "", 0, Marker::SPHERE);
  clear.action = Marker::DELETEALL;
  out.markers.push_back(clear);

  Marker head_sphere = baseMarker(frame, stamp, "listener", 0, Marker::SPHERE);
  head_sphere.pose.position = toPoint(listener_m);
  head_sphere.scale.x = head_sphere.scale.y = head_sphere.scale.z = 0.2;
  head_sphere.color = rgba({0.9f, 0.8f, 0.7f}, 1.0f);
  out.markers.push_back(head_sphere);
  Marker facing = baseMarker(frame, stamp, "listener", 1, Marker::ARROW);
  facing.pose.position = toPoint(listener_m);
  facing.pose.orientation.x = head.x();
  facing.pose.orientation.y = head.y();
  facing.pose.orientation.z = head.z();
  facing.pose.orientation.w = head.w();
  facing.scale.x = 0.35;
  facing.scale.y = facing.scale.z = 0.04;
  facing.color = rgba({0.9f, 0.2f, 0.2f}, 1.0f);
  out.markers.push_back(facing);

  Marker source = baseMarker(frame, stamp, "source", 0, Marker::SPHERE);
  source.pose.position = toPoint(source_m);
  source.scale.x = source.scale.y = source.scale.z = 0.25;
  source.color = rgba(anchorColor(core::ReflectionAnchor::kSource), 1.0f);
  out.markers.push_back(source);

  Marker images = baseMarker(frame, stamp, "image_sources", 0, Marker::SPHERE_LIST);
  images.scale.x = images.scale.y = images.scale.z = 0.12;
  Marker lines = baseMarker(frame, stamp, "reflection_paths", 0, Marker::LINE_LIST);
  lines.scale.x = 0.015;
  // Faded from the direct sound's level (the loudest path's when it is not heard).
  double reference = 0.0, loudest = 0.0;
  for (const DrawnPath& path : paths) {
    if (path.direct) reference = std::abs(path.level);
    loudest = std::max(loudest, std::abs(path.level));
  }
  reference = std::max(reference > 0.0 ? reference : loudest, 1e-12);
  for (const DrawnPath& path : paths) {
    const double db = 20.0 * std::log10(std::max(std::abs(path.level), 1e-12) / reference);
    const auto alpha = static_cast<float>(std::clamp(1.0 + db / 40.0 * 0.85, 0.15, 1.0));
    const std_msgs::ColorRGBA color = rgba(path.rgb, alpha);
    if (path.image_source_m) {
      images.points.push_back(toPoint(*path.image_source_m));
      images.colors.push_back(color);
    }
    for (std::size_t i = 1; i < path.points.size(); ++i) {
      lines.points.push_back(toPoint(path.points[i - 1]));
      lines.points.push_back(toPoint(path.points[i]));
      lines.colors.push_back(color);
      lines.colors.push_back(color);
    }
  }
  // rviz refuses an empty list marker: add them only when they hold something.
  if (!images.points.empty()) out.markers.push_back(images);
  if (!lines.points.empty()) out.markers.push_back(lines);
  return out;
}

}  // namespace room_reverb::ros_bridge
