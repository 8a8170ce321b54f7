#pragma once
// The EstimateRsao service over the core's RSAO estimator, with the last estimate published
// latched on ~rsao and drawn for rviz on ~markers.
#include <ros/ros.h>
#include <room_reverb/EstimateRsao.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>

#include "room_reverb/rsao/rsao_estimator.h"

namespace room_reverb::ros_bridge {

// The reflections as spheres around the microphone: each at its direction and at distance
// c * toa (scaled by distance_scale), sized by its level relative to the direct sound; the
// direct sound green, reflections coloured from yellow (strong) to blue (weak), each with
// a text label of its time and level. Frame: `frame_id`.
visualization_msgs::MarkerArray rsaoMarkers(const core::Rsao& rsao, const std::string& frame_id,
                                            double distance_scale, double max_sphere_m);

class RsaoEstimatorServer {
 public:
  // Parameters are read once and checked loudly (config/rsao_estimator.yaml documents them).
  explicit RsaoEstimatorServer(::ros::NodeHandle& private_nh);

  // The service body, callable without ROS for tests. Never throws: bad input gives
  // success=false and a message.
  bool estimate(room_reverb::EstimateRsao::Request& request, room_reverb::EstimateRsao::Response& response);

  // RIRs arriving on ~impulse_response (a rig's measurement, or a bag replayed): estimated
  // with the node's parameters, the convention taken from audio.channel_layout ("fuma" or
  // "ambix"); the result is published as for a service call, a failure logged.
  void onImpulseResponse(const room_reverb::ImpulseResponse::ConstPtr& message);

 private:
  core::RsaoOptions defaults_;
  std::string frame_id_;
  std::string room_frame_;
  double marker_distance_scale_ = 1.0;
  double marker_max_sphere_m_ = 0.5;
  ::ros::Publisher rsao_publisher_;
  ::ros::Publisher marker_publisher_;
  ::ros::ServiceServer server_;
  ::ros::Subscriber subscriber_;
};

}  // namespace room_reverb::ros_bridge
