#pragma once
// The evaluation node's services over the core's comparison and diagnosis:
// ~compare (room_reverb/CompareMeasurement) and ~diagnose (room_reverb/DiagnoseRoom).
// A diagnosis of a room model also publishes the corrected room, latched, on
// ~corrected_room (room_reverb/RoomModel).
//
// The live system's closed loop: with ~auto_diagnose, the node listens to the visual
// route's room model (~room) and the rig's measured RIR (~impulse_response, with its
// source and receiver positions); whenever both are there and either changes, it
// diagnoses the room model against the RIR in the background and publishes the corrected
// room on ~corrected_room and, for the binaural renderer, ~corrected_scene
// (room_reverb/RoomScene: the corrected room heard at the measured positions).
#include <ros/ros.h>
#include <room_reverb/CompareMeasurement.h>
#include <room_reverb/DiagnoseRoom.h>
#include <room_reverb/ImpulseResponse.h>
#include <room_reverb/RoomModel.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/simulation_runner.h"

namespace room_reverb::ros_bridge {

class EvaluationServer {
 public:
  // Parameters (config/evaluation.yaml) are read once and checked loudly.
  explicit EvaluationServer(::ros::NodeHandle& private_nh);
  ~EvaluationServer();
  EvaluationServer(const EvaluationServer&) = delete;
  EvaluationServer& operator=(const EvaluationServer&) = delete;

  // The service bodies, callable without ROS for tests. Never throw: bad input gives
  // success=false and a message.
  bool compare(room_reverb::CompareMeasurement::Request& request, room_reverb::CompareMeasurement::Response& response);
  bool diagnose(room_reverb::DiagnoseRoom::Request& request, room_reverb::DiagnoseRoom::Response& response);

 private:
  void onRoom(const room_reverb::RoomModel::ConstPtr& message);
  void onImpulseResponse(const room_reverb::ImpulseResponse::ConstPtr& message);
  // Starts the live worker unless it runs; the worker diagnoses the newest inputs until
  // none changed during its last diagnosis.
  void scheduleLiveDiagnosis();
  void liveLoop();
  void liveDiagnosis(room_reverb::RoomModel room, room_reverb::ImpulseResponse rir);
  // Publishes a corrected room (and its scene at `rir`'s positions when given).
  void publishCorrection(const room_reverb::RoomModel& room, const room_reverb::ImpulseResponse* rir);

  int rays_ = 20000;           // compare
  int diagnosis_rays_ = 10000;
  int seed_ = 1;
  int max_causes_ = 3;
  int noise_seeds_ = 5;  // ~noise_seeds
  std::vector<std::string> causes_;  // ~causes: tried when a request names none; empty: the catalogue
  int threads_ = 0;
  // ~simulators or ~simulation_workers: where the simulations run (null: this process).
  std::shared_ptr<core::SimulationRunner> runner_;
  std::string out_root_;
  core::MaterialLibrary library_;
  ::ros::ServiceServer compare_server_, diagnose_server_;
  ::ros::Publisher corrected_room_publisher_, corrected_scene_publisher_;
  ::ros::Subscriber room_subscriber_, rir_subscriber_;
  std::mutex live_mutex_;
  std::optional<room_reverb::RoomModel> live_room_;
  std::optional<room_reverb::ImpulseResponse> live_rir_;
  bool live_dirty_ = false;
  bool live_running_ = false;  // guarded by live_mutex_
  std::thread live_thread_;
};

}  // namespace room_reverb::ros_bridge
