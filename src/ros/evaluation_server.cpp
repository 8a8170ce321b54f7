#include "room_reverb/ros/evaluation_server.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <room_reverb/RoomScene.h>
#include <sstream>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/worker_process.h"
#include "room_reverb/diagnosis/diagnosis_output.h"
#include "room_reverb/diagnosis/diagnosis_setup.h"
#include "room_reverb/evaluation/measurement_comparison.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/parameters.h"
#include "room_reverb/ros/room_conversions.h"
#include "room_reverb/ros/service_simulation_runner.h"

namespace room_reverb::ros_bridge {
namespace {

bool hasRoomModel(const room_reverb::RoomModel& room) { return room.size.x > 0.0; }

void requireOneRoom(const room_reverb::RoomModel& room, const std::string& mesh_file) {
  if (hasRoomModel(room) && !mesh_file.empty()) throw core::InputError("give a room model or a mesh file, not both");
}

double nanIfEmpty(const std::optional<double>& v) { return v ? *v : std::numeric_limits<double>::quiet_NaN(); }

// What both services check and read first.
template <class Request>
core::Measurements measurementsOf(const Request& request) {
  if (request.rays < 0 || request.seed < 0 || request.duration_s < 0.0) {
    throw core::InputError("rays, seed and duration_s must not be negative (0: the node's parameter)");
  }
  requireOneRoom(request.room, request.mesh_file);
  return core::loadMeasurements(request.measurements_file);
}

// The room a request names: its RoomModel, its mesh file, or else the room or mesh of the
// measurements file. `no_air`: a model without air absorption.
core::RoomUnderTest roomOf(const room_reverb::RoomModel& message, const std::string& mesh_file, bool mesh_y_up,
                           const core::Measurements& measurements, bool no_air, const core::MaterialLibrary& library) {
  if (hasRoomModel(message)) {
    core::RoomModel model = fromMessage(message);
    if (no_air) model.air.enabled = false;
    return core::RoomUnderTest::fromRoomModel(model, library);
  }
  if (!mesh_file.empty()) {
    return core::loadRoomUnderTest("", mesh_file, mesh_y_up ? core::UpAxis::kY : core::UpAxis::kZ, measurements, no_air,
                                   library);
  }
  return core::loadRoomUnderTest(measurements.room_file, measurements.mesh_file, measurements.mesh_up_axis, measurements,
                                 no_air, library);
}

bool finite(const geometry_msgs::Point& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// What the live diagnosis would refuse in a RIR, refused on arrival (the layout is also
// written into measurements.yaml, so only the known names pass).
void checkLiveImpulseResponse(const room_reverb::ImpulseResponse& rir) {
  fromMessage(rir.audio);
  const std::string& layout = rir.audio.channel_layout;
  if (layout != "mono" && layout != "fuma" && layout != "ambix") {
    throw core::InputError("channel_layout \"" + layout + "\" is not mono, fuma or ambix");
  }
  if (!finite(rir.source_position) || !finite(rir.receiver_position)) {
    throw core::InputError("the source or receiver position is not finite");
  }
}

// A new folder name under `root`: PREFIX_<milliseconds since 1970>.
std::filesystem::path stampedFolder(const std::string& root, const std::string& prefix) {
  const auto stamp = std::chrono::duration_cast<std::chrono::milliseconds>(
                         std::chrono::system_clock::now().time_since_epoch()).count();
  return std::filesystem::path(root) / (prefix + "_" + std::to_string(stamp));
}

}  // namespace

EvaluationServer::EvaluationServer(::ros::NodeHandle& private_nh) {
  rays_ = positiveIntParam(private_nh, "compare_rays", 20000);
  diagnosis_rays_ = positiveIntParam(private_nh, "diagnosis_rays", 10000);
  seed_ = positiveIntParam(private_nh, "seed", 1);
  max_causes_ = positiveIntParam(private_nh, "max_causes", 3);
  noise_seeds_ = positiveIntParam(private_nh, "noise_seeds", core::DiagnosisOptions{}.noise_seeds);
  if (noise_seeds_ > core::DiagnosisOptions::kMaxNoiseSeeds) {
    throw core::InputError("parameter ~noise_seeds must be 1-" + std::to_string(core::DiagnosisOptions::kMaxNoiseSeeds));
  }
  causes_ = stringListParam(private_nh, "causes");
  try {
    for (const std::string& cause : causes_) core::requireKnownCause(cause);
  } catch (const core::InputError& e) {
    throw core::InputError(std::string("parameter ~causes: ") + e.what());
  }
  typedParam(private_nh, "threads", threads_, 0);
  if (threads_ < 0) throw core::InputError("parameter ~threads must not be negative");
  const std::vector<std::string> simulators = stringListParam(private_nh, "simulators");
  int workers = 0;
  typedParam(private_nh, "simulation_workers", workers, 0);
  if (workers < 0 || workers > 256) throw core::InputError("parameter ~simulation_workers must be 0 to 256");
  double wait_s = 10.0;
  typedParam(private_nh, "simulator_wait_s", wait_s, 10.0);
  if (!(wait_s >= 0.0)) throw core::InputError("parameter ~simulator_wait_s must not be negative");
  if (!simulators.empty() && workers > 0) {
    throw core::InputError("parameters ~simulators and ~simulation_workers: give one of them, not both");
  }
  if (!simulators.empty()) runner_ = std::make_shared<ServiceSimulationRunner>(simulators, wait_s);
  if (workers > 0) {
    // The tool stands next to this node's executable (devel/lib/room_reverb, or the install's).
    const std::string tool = (std::filesystem::path(core::executablePath()).parent_path() / "room_reverb").string();
    core::requireExistingFile(tool, "room_reverb tool", "the workers of ~simulation_workers run it");
    runner_ = std::make_shared<core::WorkerProcessSimulationRunner>(core::localWorkerCommands(workers, tool));
  }
  if (runner_) ROS_INFO("evaluation: simulations run on %s", runner_->description().c_str());
  typedParam(private_nh, "out_root", out_root_, std::string("/tmp/room_reverb_evaluation"));
  std::string materials_file;
  typedParam(private_nh, "materials_file", materials_file, std::string(""));
  library_ = materials_file.empty() ? core::MaterialLibrary::loadDefault() : core::MaterialLibrary::load(materials_file);
  corrected_room_publisher_ = private_nh.advertise<room_reverb::RoomModel>("corrected_room", 1, true);
  corrected_scene_publisher_ = private_nh.advertise<room_reverb::RoomScene>("corrected_scene", 1, true);
  bool auto_diagnose = false;
  typedParam(private_nh, "auto_diagnose", auto_diagnose, false);
  if (auto_diagnose) {
    room_subscriber_ = private_nh.subscribe("room", 1, &EvaluationServer::onRoom, this);
    rir_subscriber_ = private_nh.subscribe("impulse_response", 1, &EvaluationServer::onImpulseResponse, this);
  }
  compare_server_ = private_nh.advertiseService("compare", &EvaluationServer::compare, this);
  diagnose_server_ = private_nh.advertiseService("diagnose", &EvaluationServer::diagnose, this);
}

EvaluationServer::~EvaluationServer() {
  if (live_thread_.joinable()) live_thread_.join();
}

void EvaluationServer::publishCorrection(const room_reverb::RoomModel& room, const room_reverb::ImpulseResponse* rir) {
  corrected_room_publisher_.publish(room);
  if (rir == nullptr) return;
  room_reverb::RoomScene scene;
  scene.room = room;
  scene.source = rir->source_position;
  scene.listener = rir->receiver_position;
  scene.mode = "accurate";
  corrected_scene_publisher_.publish(scene);
}

void EvaluationServer::onRoom(const room_reverb::RoomModel::ConstPtr& message) {
  try {
    // Refused now, not at the next live diagnosis (which waits for a RIR): the last good
    // room stays.
    core::roomModelToScene(fromMessage(*message), library_);
  } catch (const std::exception& e) {
    ROS_WARN("evaluation: ~room ignored, the last good one stays: %s", e.what());
    return;
  }
  {
    std::lock_guard<std::mutex> lock(live_mutex_);
    live_room_ = *message;
    live_dirty_ = true;
  }
  scheduleLiveDiagnosis();
}

void EvaluationServer::onImpulseResponse(const room_reverb::ImpulseResponse::ConstPtr& message) {
  if (!message->positions_known) {
    ROS_WARN("evaluation: ~impulse_response without source and receiver positions: not diagnosed");
    return;
  }
  try {
    checkLiveImpulseResponse(*message);
  } catch (const std::exception& e) {
    ROS_WARN("evaluation: ~impulse_response ignored, the last good one stays: %s", e.what());
    return;
  }
  {
    std::lock_guard<std::mutex> lock(live_mutex_);
    live_rir_ = *message;
    live_dirty_ = true;
  }
  scheduleLiveDiagnosis();
}

void EvaluationServer::scheduleLiveDiagnosis() {
  std::lock_guard<std::mutex> lock(live_mutex_);
  if (!live_room_ || !live_rir_ || !live_dirty_ || live_running_) return;
  live_running_ = true;
  // The previous worker has left its loop (it clears live_running_ under this lock and
  // returns), so this join is immediate.
  if (live_thread_.joinable()) live_thread_.join();
  live_thread_ = std::thread([this] { liveLoop(); });
}

void EvaluationServer::liveLoop() {
  for (;;) {
    room_reverb::RoomModel room;
    room_reverb::ImpulseResponse rir;
    {
      std::lock_guard<std::mutex> lock(live_mutex_);
      // Inputs that changed during a diagnosis are diagnosed again, newest first.
      if (!live_dirty_) {
        live_running_ = false;
        return;
      }
      live_dirty_ = false;
      room = *live_room_;
      rir = *live_rir_;
    }
    liveDiagnosis(room, rir);
  }
}

void EvaluationServer::liveDiagnosis(room_reverb::RoomModel room, room_reverb::ImpulseResponse rir) {
  try {
    const std::filesystem::path dir = stampedFolder(out_root_, "live");
    core::createFolder(dir.string());
    // The measurement as the core reads it: the RIR as a file, its pair in measurements.yaml.
    core::writeAudioFile((dir / "measured_rir.wav").string(), fromMessage(rir.audio));
    const std::string layout = rir.audio.channel_layout == "mono" ? "omni" : rir.audio.channel_layout;
    std::ostringstream yaml;
    yaml << "pairs:\n  - {file: measured_rir.wav, format: " << layout << ", source_m: [" << rir.source_position.x << ", "
         << rir.source_position.y << ", " << rir.source_position.z << "], receiver_m: [" << rir.receiver_position.x << ", "
         << rir.receiver_position.y << ", " << rir.receiver_position.z << "]}\n";
    core::writeTextFile((dir / "measurements.yaml").string(), yaml.str());

    room_reverb::DiagnoseRoom::Request request;
    room_reverb::DiagnoseRoom::Response response;
    request.measurements_file = (dir / "measurements.yaml").string();
    request.room = room;
    request.max_causes = -1;
    request.out_dir = (dir / "diagnosis").string();
    diagnose(request, response);
    if (!response.success) {
      ROS_WARN("evaluation: live diagnosis failed: %s", response.message.c_str());
      return;
    }
    ROS_INFO("evaluation: live diagnosis: %zu causes named (baseline %.2f JND, noise %.2f); %s", response.causes.size(),
             response.baseline_error_jnd, response.noise_jnd, request.out_dir.c_str());
    publishCorrection(response.extended_room, &rir);
  } catch (const std::exception& e) {
    ROS_WARN("evaluation: live diagnosis failed: %s", e.what());
  }
}

bool EvaluationServer::compare(room_reverb::CompareMeasurement::Request& request,
                               room_reverb::CompareMeasurement::Response& response) {
  try {
    const core::Measurements measurements = measurementsOf(request);
    const core::MeasuredEvidence evidence = core::measuredEvidence(measurements);
    core::SimulationSettings settings;
    settings.rays.ray_count = static_cast<std::size_t>(request.rays > 0 ? request.rays : rays_);
    settings.rays.seed = static_cast<std::uint32_t>(request.seed > 0 ? request.seed : seed_);
    settings.rays.threads = threads_;
    settings.duration_s = request.duration_s > 0.0 ? request.duration_s : core::diagnosisDurationS(evidence);
    const core::RoomUnderTest room =
        roomOf(request.room, request.mesh_file, request.mesh_y_up, measurements, false, library_);
    settings.air = room.airWith({});
    const core::MeasurementComparison comparison =
        core::compareMeasurement(room.scene({}), evidence, settings, {}, runner_.get());
    for (const core::BandComparison& row : comparison.average) {
      for (core::ComparedParameter p : core::kComparedParameters) {
        const auto i = static_cast<std::size_t>(p);
        if (!row.measured[i]) continue;
        response.parameter.push_back(core::toString(p));
        response.band_hz.push_back(row.nominal_hz);
        response.simulated.push_back(nanIfEmpty(row.simulated[i]));
        response.measured.push_back(*row.measured[i]);
        response.error_jnd.push_back(nanIfEmpty(row.error_jnd[i]));
      }
    }
    response.mean_abs_error_jnd = nanIfEmpty(core::summarizeComparison(comparison.average).overall_mean_abs_error_jnd);
    response.pairs = static_cast<std::uint32_t>(comparison.pairs.size());
    response.comparison_json = core::comparisonToJson(comparison);
    if (!request.out_dir.empty()) core::writeComparison(comparison, request.out_dir);
    response.success = true;
  } catch (const std::exception& e) {
    response = room_reverb::CompareMeasurement::Response();
    response.success = false;
    response.message = e.what();
  }
  return true;
}

bool EvaluationServer::diagnose(room_reverb::DiagnoseRoom::Request& request,
                                room_reverb::DiagnoseRoom::Response& response) {
  try {
    const core::Measurements measurements = measurementsOf(request);
    const core::MeasuredEvidence evidence = core::measuredEvidence(measurements);
    const core::RoomUnderTest room =
        roomOf(request.room, request.mesh_file, request.mesh_y_up, measurements, request.no_air, library_);
    core::DiagnosisOptions options;
    if (!request.causes.empty()) {
      options.causes = request.causes;
    } else if (!causes_.empty()) {
      options.causes = causes_;
    }
    options.max_causes = request.max_causes >= 0 ? request.max_causes : max_causes_;
    options.noise_seeds = noise_seeds_;
    core::SimulationSettings& sim = options.evaluation.simulation;
    sim.rays.ray_count = static_cast<std::size_t>(request.rays > 0 ? request.rays : diagnosis_rays_);
    sim.rays.seed = static_cast<std::uint32_t>(request.seed > 0 ? request.seed : seed_);
    sim.rays.threads = threads_;
    sim.duration_s = request.duration_s > 0.0 ? request.duration_s : core::diagnosisDurationS(evidence);
    options.evaluation.runner = runner_;

    const core::Diagnosis diagnosis = core::diagnose(room, evidence, options);
    const std::string out = request.out_dir.empty() ? stampedFolder(out_root_, "diagnosis").string() : request.out_dir;
    const core::DiagnosisFiles files = core::writeDiagnosis(diagnosis, room, evidence, out);
    response.baseline_error_jnd = diagnosis.baseline_error_jnd;
    response.noise_jnd = diagnosis.noise_jnd;
    response.threshold_jnd = diagnosis.threshold_jnd;
    for (const core::NamedCause& c : diagnosis.causes) {
      room_reverb::DiagnosedCause m;
      m.cause = c.cause;
      m.target = c.target;
      m.parameters_json = core::describeParameters(c.parameters);
      m.error_before_jnd = c.error_before_jnd;
      m.error_after_jnd = c.error_after_jnd;
      m.heldout_gain_jnd = c.heldoutGainJnd();
      m.heldout_gain_over_seeds_jnd = c.over_seeds.mean_jnd;
      m.heldout_gain_standard_error_jnd = c.over_seeds.standard_error_jnd;
      response.causes.push_back(m);
    }
    if (room.isRoomModel()) {
      response.extended_room = toMessage(room.extendedRoomModel(diagnosis.extension));
      response.extended_room.header.frame_id = "room";
      response.extended_room.header.stamp = ::ros::Time::now();
      response.has_extended_room = true;
      // The room the evidence supports (the input itself when nothing was named).
      if (request.publish_correction) publishCorrection(response.extended_room, nullptr);
    }
    response.out_dir = out;
    response.diagnosis_json = core::readTextFile(files.json, "diagnosis.json");
    response.success = true;
  } catch (const std::exception& e) {
    response = room_reverb::DiagnoseRoom::Response();
    response.success = false;
    response.message = e.what();
  }
  return true;
}

}  // namespace room_reverb::ros_bridge
