// rostest: the evaluation node with its simulations on two room_simulator nodes
// (launch/distributed_evaluation.launch). Its comparison and its diagnosis must be what
// this process computes with the same settings in one process, to the bit.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <room_reverb/CompareMeasurement.h>
#include <room_reverb/DiagnoseRoom.h>
#include <room_reverb/SimulateJob.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/acoustics/simulation_wire.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/diagnosis/diagnosis.h"
#include "room_reverb/diagnosis/diagnosis_setup.h"
#include "room_reverb/evaluation/measurement_comparison.h"
#include "room_reverb/ros/room_conversions.h"
#include "test_files.h"
#include "test_rooms.h"
#include "tool_run.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

const Eigen::Vector3d kSource1(1.2, 1.0, 1.4), kReceiver1(3.6, 2.8, 1.3);
const Eigen::Vector3d kSource2(4.0, 1.1, 1.6), kReceiver2(1.5, 2.9, 1.2);

// Two B-format "measurements" of the studio with its air at 35 % (the model's is 50 %).
std::string measurementsFile() {
  static const std::string path = [] {
    core::RoomModel room = parseRoomModel(kStudioRoomYaml);
    room.air.humidity_percent = 35.0;
    const AcousticScene scene = roomModelToScene(room, MaterialLibrary::loadDefault());
    SimulationSettings s;
    s.rays.ray_count = 8000;
    s.rays.seed = 501;
    s.duration_s = 0.8;
    s.air = room.air;
    const std::string a = tempPath("d1.wav").string(), b = tempPath("d2.wav").string();
    writeAudioFile(a, simulateRoom(scene, kSource1, kReceiver1, s).impulse_response);
    s.rays.seed = 502;
    writeAudioFile(b, simulateRoom(scene, kSource2, kReceiver2, s).impulse_response);
    return writeFile("distributed_measurements.yaml",
                     "pairs:\n  - {file: " + a + ", format: ambix, source_m: [1.2, 1.0, 1.4], receiver_m: [3.6, 2.8, 1.3]}\n"
                     "  - {file: " + b + ", format: ambix, source_m: [4.0, 1.1, 1.6], receiver_m: [1.5, 2.9, 1.2]}\n");
  }();
  return path;
}

class DistributedEvaluation : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : {"/evaluation/compare", "/evaluation/diagnose", "/simulator_a/simulate_job",
                             "/simulator_b/simulate_job"}) {
      ASSERT_TRUE(ros::service::waitForService(name, ros::Duration(30.0))) << name;
    }
  }
  RoomUnderTest room() const { return RoomUnderTest::fromRoomModel(parseRoomModel(kStudioRoomYaml), MaterialLibrary::loadDefault()); }
  ros::NodeHandle nh_;
};

TEST_F(DistributedEvaluation, CompareIsWhatOneProcessComputes) {
  room_reverb::CompareMeasurement srv;
  srv.request.measurements_file = measurementsFile();
  srv.request.room = ros_bridge::toMessage(parseRoomModel(kStudioRoomYaml));
  srv.request.rays = 3000;
  srv.request.duration_s = 0.8;
  ASSERT_TRUE(ros::service::call("/evaluation/compare", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;

  // The node's settings (config/evaluation.yaml: seed 1, threads 0), in this process.
  const MeasuredEvidence evidence = measuredEvidence(loadMeasurements(measurementsFile()));
  const RoomUnderTest here = room();
  SimulationSettings settings;
  settings.rays.ray_count = 3000;
  settings.rays.seed = 1;
  settings.duration_s = 0.8;
  settings.air = here.airWith({});
  const MeasurementComparison local = compareMeasurement(here.scene({}), evidence, settings);
  std::size_t k = 0;
  for (const BandComparison& row : local.average) {
    for (ComparedParameter p : kComparedParameters) {
      const auto i = static_cast<std::size_t>(p);
      if (!row.measured[i]) continue;
      ASSERT_LT(k, srv.response.simulated.size());
      EXPECT_EQ(srv.response.parameter[k], toString(p));
      if (row.simulated[i]) {
        EXPECT_EQ(srv.response.simulated[k], *row.simulated[i]) << toString(p) << " " << row.nominal_hz;
      } else {
        EXPECT_TRUE(std::isnan(srv.response.simulated[k])) << toString(p) << " " << row.nominal_hz;
      }
      ++k;
    }
  }
  EXPECT_EQ(k, srv.response.simulated.size());
  EXPECT_GT(k, 20u);
}

TEST_F(DistributedEvaluation, DiagnoseNamesWhatOneProcessNames) {
  room_reverb::DiagnoseRoom srv;
  srv.request.measurements_file = measurementsFile();
  srv.request.room = ros_bridge::toMessage(parseRoomModel(kStudioRoomYaml));
  srv.request.causes = {"air_absorption"};
  srv.request.max_causes = 1;
  srv.request.rays = 1500;
  srv.request.duration_s = 0.8;
  srv.request.out_dir = tempPath("distributed_diagnosis").string();
  ASSERT_TRUE(ros::service::call("/evaluation/diagnose", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;

  const MeasuredEvidence evidence = measuredEvidence(loadMeasurements(measurementsFile()));
  DiagnosisOptions options;
  options.causes = {"air_absorption"};
  options.max_causes = 1;
  options.noise_seeds = 2;  // the test's launch file
  options.evaluation.simulation.rays.ray_count = 1500;
  options.evaluation.simulation.rays.seed = 1;
  options.evaluation.simulation.duration_s = 0.8;
  const Diagnosis local = diagnose(room(), evidence, options);
  EXPECT_EQ(srv.response.baseline_error_jnd, local.baseline_error_jnd);
  EXPECT_EQ(srv.response.noise_jnd, local.noise_jnd);
  EXPECT_EQ(srv.response.threshold_jnd, local.threshold_jnd);
  ASSERT_EQ(srv.response.causes.size(), local.causes.size()) << srv.response.diagnosis_json;
  for (std::size_t i = 0; i < local.causes.size(); ++i) {
    EXPECT_EQ(srv.response.causes[i].cause, local.causes[i].cause);
    EXPECT_EQ(srv.response.causes[i].heldout_gain_jnd, local.causes[i].heldoutGainJnd());
  }
  const nlohmann::json j = nlohmann::json::parse(srv.response.diagnosis_json);
  EXPECT_EQ(j["simulations"].get<int>(), local.simulations);
}

TEST_F(DistributedEvaluation, ASimulatorRefusesABrokenJobWithAReason) {
  room_reverb::SimulateJob srv;
  srv.request.job = {1, 2, 3, 4, 5};
  ASSERT_TRUE(ros::service::call("/simulator_a/simulate_job", srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_TRUE(srv.response.input_error);
  EXPECT_NE(srv.response.message.find("simulation job"), std::string::npos) << srv.response.message;
  // More rays than the node's ~max_rays (config/room_simulator.yaml: 10^7).
  SimulationRequest request;
  request.source_m = kSource1;
  request.listener_m = kReceiver1;
  request.settings.rays.ray_count = 20000000;
  request.settings.rays.threads = 1;
  srv.request.job = encodeJob(encodeScene(room().scene({})), request);
  ASSERT_TRUE(ros::service::call("/simulator_a/simulate_job", srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("max_rays"), std::string::npos) << srv.response.message;
}

TEST(EvaluationNode, AMissingSimulatorStopsTheNodeNamingIt) {
  ros::param::set("/evaluation_no_simulator/simulators", std::vector<std::string>{"/nobody/simulate_job"});
  ros::param::set("/evaluation_no_simulator/simulator_wait_s", 0.5);
  ToolRun run = runSiblingNode("evaluation", "evaluation_no_simulator", 20);
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("no service /nobody/simulate_job"), std::string::npos) << run.err;

  ros::param::set("/evaluation_both_runners/simulators", std::vector<std::string>{"/simulator_a/simulate_job"});
  ros::param::set("/evaluation_both_runners/simulation_workers", 2);
  run = runSiblingNode("evaluation", "evaluation_both_runners", 20);
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("not both"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace room_reverb::test

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_distributed_evaluation");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
