#include "room_reverb/ros/parameters.h"
#include "room_reverb/ros/rsao_estimator_server.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/common/error.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/rsao_conversions.h"

namespace room_reverb::ros_bridge {
namespace {

std_msgs::ColorRGBA color(double r, double g, double b) {
  std_msgs::ColorRGBA c;
  c.r = static_cast<float>(r);
  c.g = static_cast<float>(g);
  c.b = static_cast<float>(b);
  c.a = 0.9f;
  return c;
}

void requirePositive(bool ok, const std::string& name) {
  if (!ok) throw core::InputError("parameter ~" + name + " must be positive");
}

// A white text label `lift_m` above a marker, in its frame.
visualization_msgs::Marker labelAbove(const visualization_msgs::Marker& marker, const std::string& ns, double lift_m,
                                      const std::string& text) {
  visualization_msgs::Marker label = marker;
  label.ns = ns;
  label.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  label.pose.position.z += lift_m;
  label.scale.x = label.scale.y = 0.0;
  label.scale.z = 0.12;
  label.color = color(1.0, 1.0, 1.0);
  label.text = text;
  return label;
}

// A sphere and its name at a position in `frame`.
void appendPositionMarker(visualization_msgs::MarkerArray& array, const std::string& frame, int id,
                          const geometry_msgs::Point& at, const std::string& name, const std_msgs::ColorRGBA& rgba) {
  visualization_msgs::Marker sphere;
  sphere.header.frame_id = frame;
  sphere.ns = "source_listener";
  sphere.id = id;
  sphere.type = visualization_msgs::Marker::SPHERE;
  sphere.action = visualization_msgs::Marker::ADD;
  sphere.pose.position = at;
  sphere.pose.orientation.w = 1.0;
  sphere.scale.x = sphere.scale.y = sphere.scale.z = 0.25;
  sphere.color = rgba;
  array.markers.push_back(sphere);
  array.markers.push_back(labelAbove(sphere, "source_listener_labels", 0.3, name));
}

}  // namespace

visualization_msgs::MarkerArray rsaoMarkers(const core::Rsao& rsao, const std::string& frame_id,
                                            double distance_scale, double max_sphere_m) {
  visualization_msgs::MarkerArray array;
  visualization_msgs::Marker clear;
  clear.action = visualization_msgs::Marker::DELETEALL;
  array.markers.push_back(clear);
  if (rsao.reflections.empty()) return array;
  const double direct = rsao.reflections.front().level;
  for (std::size_t k = 0; k < rsao.reflections.size(); ++k) {
    const core::EarlyReflection& r = rsao.reflections[k];
    const double relative_db = direct > 0.0 && r.level > 0.0 ? 20.0 * std::log10(r.level / direct) : -60.0;
    // 0 dB (the direct sound) draws max_sphere_m wide, -40 dB a tenth of it.
    const double strength = std::clamp(1.0 + relative_db / 40.0, 0.0, 1.0);
    const double radius = distance_scale * r.distance_m;
    visualization_msgs::Marker sphere;
    sphere.header.frame_id = frame_id;
    sphere.ns = "rsao_reflections";
    sphere.id = static_cast<int>(k);
    sphere.type = visualization_msgs::Marker::SPHERE;
    sphere.action = visualization_msgs::Marker::ADD;
    sphere.pose.position.x = radius * std::cos(r.elevation_rad) * std::cos(r.azimuth_rad);
    sphere.pose.position.y = radius * std::cos(r.elevation_rad) * std::sin(r.azimuth_rad);
    sphere.pose.position.z = radius * std::sin(r.elevation_rad);
    sphere.pose.orientation.w = 1.0;
    sphere.scale.x = sphere.scale.y = sphere.scale.z = max_sphere_m * (0.1 + 0.9 * strength);
    sphere.color = k == 0 ? color(0.1, 0.9, 0.2) : color(1.0, strength, 1.0 - strength);
    array.markers.push_back(sphere);

    char text[64];
    std::snprintf(text, sizeof text, k == 0 ? "direct %.1f ms" : "%.1f ms %.1f dB", 1000.0 * r.time_of_arrival_s,
                  relative_db);
    array.markers.push_back(labelAbove(sphere, "rsao_labels", 0.6 * sphere.scale.z + 0.05, text));
  }
  return array;
}

RsaoEstimatorServer::RsaoEstimatorServer(::ros::NodeHandle& private_nh) {
  typedParam(private_nh, "frame_id", frame_id_, std::string("rig"));
  typedParam(private_nh, "room_frame", room_frame_, std::string("room"));
  int max_reflections = 40;
  typedParam(private_nh, "max_reflections", max_reflections, 40);
  if (max_reflections < 0) throw core::InputError("parameter ~max_reflections must be 0 or more");
  defaults_.early.max_reflections = static_cast<std::size_t>(max_reflections);
  typedParam(private_nh, "analysis_window_s", defaults_.early.analysis_window_s, 0.002);
  typedParam(private_nh, "lpc_order", defaults_.early.lpc_order, 9);
  bool paper_lpc = false;
  typedParam(private_nh, "paper_lpc", paper_lpc, false);
  if (paper_lpc) defaults_.early.lpc_flat_below_hz = 0.0;
  typedParam(private_nh, "fit_onset_ramps", defaults_.fit_onset_ramps, true);
  typedParam(private_nh, "two_slope_decays", defaults_.late.two_slopes, true);
  bool paper_onsets = false;
  typedParam(private_nh, "paper_onsets", paper_onsets, false);
  defaults_.early.onset_method = paper_onsets ? core::OnsetMethod::kGroupDelay : core::OnsetMethod::kMatchedPursuit;
  typedParam(private_nh, "min_direct_prominence_db", defaults_.min_direct_prominence_db, 15.0);
  typedParam(private_nh, "marker_distance_scale", marker_distance_scale_, 1.0);
  typedParam(private_nh, "marker_max_sphere_m", marker_max_sphere_m_, 0.5);
  requirePositive(marker_distance_scale_ > 0.0, "marker_distance_scale");
  requirePositive(marker_max_sphere_m_ > 0.0, "marker_max_sphere_m");
  core::validateRsaoOptions(defaults_);
  rsao_publisher_ = private_nh.advertise<room_reverb::Rsao>("rsao", 1, true);
  marker_publisher_ = private_nh.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
  server_ = private_nh.advertiseService("estimate", &RsaoEstimatorServer::estimate, this);
  subscriber_ = private_nh.subscribe("impulse_response", 1, &RsaoEstimatorServer::onImpulseResponse, this);
}

void RsaoEstimatorServer::onImpulseResponse(const room_reverb::ImpulseResponse::ConstPtr& message) {
  room_reverb::EstimateRsao::Request request;
  room_reverb::EstimateRsao::Response response;
  request.impulse_response = *message;
  estimate(request, response);
  if (response.success) {
    ROS_INFO("rsao_estimator: %zu reflections, mixing time %.1f ms%s", response.rsao.reflections.size(),
             1000.0 * response.rsao.late.mixing_time_s, response.message.empty() ? "" : (", " + response.message).c_str());
  } else {
    ROS_WARN("rsao_estimator: the RIR on ~impulse_response was not estimated: %s", response.message.c_str());
  }
}

bool RsaoEstimatorServer::estimate(room_reverb::EstimateRsao::Request& request,
                                   room_reverb::EstimateRsao::Response& response) {
  try {
    core::RsaoOptions options = defaults_;
    if (request.max_reflections < 0 || request.analysis_window_s < 0.0 || request.lpc_order < 0 ||
        request.mixing_time_s < 0.0) {
      throw core::InputError("max_reflections, analysis_window_s, lpc_order and mixing_time_s must not be negative "
                             "(0: the node's parameter)");
    }
    if (request.max_reflections > 0) options.early.max_reflections = static_cast<std::size_t>(request.max_reflections);
    if (request.analysis_window_s > 0.0) options.early.analysis_window_s = request.analysis_window_s;
    if (request.lpc_order > 0) options.early.lpc_order = request.lpc_order;
    if (request.mixing_time_s > 0.0) options.mixing_time_s = request.mixing_time_s;

    core::AudioBuffer rir;
    std::string format = request.format;
    if (!request.file.empty()) {
      if (format.empty()) throw core::InputError("format is required with a file: \"fuma\" or \"ambix\"");
      rir = core::readAudioFile(request.file);
    } else {
      if (format.empty()) format = request.impulse_response.audio.channel_layout;
      if (format != "fuma" && format != "ambix") {
        throw core::InputError("the B-format convention is unknown: set format to \"fuma\" or \"ambix\" (the message's "
                               "channel_layout is \"" + request.impulse_response.audio.channel_layout + "\")");
      }
      rir = fromMessage(request.impulse_response.audio);
      if (request.impulse_response.positions_known) {
        // The direct sound's true distance places the image sources whatever latency the
        // measurement added before the RIR's first sample.
        const auto& s = request.impulse_response.source_position;
        const auto& m = request.impulse_response.receiver_position;
        const double distance = std::sqrt((s.x - m.x) * (s.x - m.x) + (s.y - m.y) * (s.y - m.y) + (s.z - m.z) * (s.z - m.z));
        if (distance > 0.0 && std::isfinite(distance)) options.early.direct_distance_m = distance;
      }
    }
    const core::Rsao rsao = core::estimateRsao(rir, core::parseAmbisonicFormat(format), options);
    response.rsao = toMessage(rsao);
    response.rsao.header.frame_id = request.file.empty() && !request.impulse_response.audio.header.frame_id.empty()
                                        ? request.impulse_response.audio.header.frame_id
                                        : frame_id_;
    response.rsao.header.stamp = request.file.empty() && !request.impulse_response.audio.header.stamp.isZero()
                                     ? request.impulse_response.audio.header.stamp
                                     : ::ros::Time::now();
    response.success = true;
    response.message = rsao.warnings.empty() ? "" : "warnings: " + rsao.warnings.front();
    rsao_publisher_.publish(response.rsao);
    visualization_msgs::MarkerArray markers =
        rsaoMarkers(rsao, response.rsao.header.frame_id, marker_distance_scale_, marker_max_sphere_m_);
    if (request.file.empty() && request.impulse_response.positions_known) {
      // The measurement's loudspeaker and microphone, where the room frame has them.
      appendPositionMarker(markers, room_frame_, 0, request.impulse_response.source_position, "source", color(1.0, 0.5, 0.0));
      appendPositionMarker(markers, room_frame_, 1, request.impulse_response.receiver_position, "listener",
                           color(0.2, 0.6, 1.0));
    }
    marker_publisher_.publish(markers);
  } catch (const std::exception& e) {
    response = room_reverb::EstimateRsao::Response();
    response.success = false;
    response.message = e.what();
  }
  return true;
}

}  // namespace room_reverb::ros_bridge
