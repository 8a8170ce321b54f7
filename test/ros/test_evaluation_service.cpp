// rostest: the evaluation node's ~compare and ~diagnose services, called as another robot
// would, on "measurements" simulated here with a known difference from the model.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <room_reverb/CompareMeasurement.h>
#include <room_reverb/DiagnoseRoom.h>
#include <room_reverb/RoomModel.h>
#include <room_reverb/RoomScene.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <tuple>
#include <nlohmann/json.hpp>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/room_conversions.h"
#include "test_files.h"
#include "tool_run.h"

namespace room_reverb::test {
namespace {

// Every face one inline material with scattering 0.5 (a diffuse room: little seed noise).
const char* kRoom = R"(frame: room
room_box: {size_m: [5.0, 4.0, 3.0], has_ceiling: true}
materials:
  test_wall: {absorption: [0.10, 0.10, 0.12, 0.14, 0.15, 0.16, 0.18, 0.20, 0.20],
              scattering: [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5]}
surfaces:
  floor: {material: test_wall}
  ceiling: {material: test_wall}
  wall_x_min: {material: test_wall}
  wall_x_max: {material: test_wall}
  wall_y_min: {material: test_wall}
  wall_y_max: {material: test_wall}
air: {enabled: true, temperature_c: 20, humidity_percent: 30}
)";

const Eigen::Vector3d kSource1(1.2, 1.0, 1.4), kReceiver1(3.6, 2.8, 1.3);
const Eigen::Vector3d kSource2(4.0, 1.1, 1.6), kReceiver2(1.5, 2.9, 1.2);

std::string measuredRir(const std::string& name, const Eigen::Vector3d& source, const Eigen::Vector3d& receiver) {
  const core::RoomModel room = core::parseRoomModel(kRoom);
  core::SimulationSettings s;
  s.rays.ray_count = 20000;
  s.rays.seed = 77;
  s.duration_s = 1.2;
  s.ambisonic_order = 1;
  s.air = room.air;
  const core::AcousticScene scene = core::roomModelToScene(room, core::MaterialLibrary::loadDefault());
  const std::string path = tempPath(name).string();
  core::writeAudioFile(path, core::simulateRoom(scene, source, receiver, s).impulse_response);
  return path;
}

// measurements.yaml with the two pairs (files made once per test process).
std::string measurementsFile() {
  static const std::string path = [] {
    const std::string a = measuredRir("m1.wav", kSource1, kReceiver1), b = measuredRir("m2.wav", kSource2, kReceiver2);
    return writeFile("measurements.yaml", "pairs:\n  - {label: P1, file: " + a +
                                              ", format: ambix, source_m: [1.2, 1.0, 1.4], receiver_m: [3.6, 2.8, 1.3]}\n"
                                              "  - {label: P2, file: " + b +
                                              ", format: ambix, source_m: [4.0, 1.1, 1.6], receiver_m: [1.5, 2.9, 1.2]}\n");
  }();
  return path;
}

room_reverb::RoomModel roomMessage() { return ros_bridge::toMessage(core::parseRoomModel(kRoom)); }

class EvaluationService : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(ros::service::waitForService("/evaluation/compare", ros::Duration(30.0)));
    ASSERT_TRUE(ros::service::waitForService("/evaluation/diagnose", ros::Duration(30.0)));
    compare_ = nh_.serviceClient<room_reverb::CompareMeasurement>("/evaluation/compare");
    diagnose_ = nh_.serviceClient<room_reverb::DiagnoseRoom>("/evaluation/diagnose");
  }

  room_reverb::CompareMeasurement::Response compare(const room_reverb::CompareMeasurement::Request& r) {
    room_reverb::CompareMeasurement srv;
    srv.request = r;
    EXPECT_TRUE(compare_.call(srv));
    return srv.response;
  }

  room_reverb::DiagnoseRoom::Response diagnose(const room_reverb::DiagnoseRoom::Request& r) {
    room_reverb::DiagnoseRoom srv;
    srv.request = r;
    EXPECT_TRUE(diagnose_.call(srv));
    return srv.response;
  }

  ros::NodeHandle nh_;
  ros::ServiceClient compare_, diagnose_;
};

double errorAt(const room_reverb::CompareMeasurement::Response& r, const std::string& parameter, double band_hz) {
  for (std::size_t i = 0; i < r.parameter.size(); ++i) {
    if (r.parameter[i] == parameter && r.band_hz[i] == band_hz) return r.error_jnd[i];
  }
  return std::nan("");
}

TEST_F(EvaluationService, CompareFindsAMoreAbsorbingModel) {
  // The model's ceiling absorbs 0.5 in every band instead of 0.10-0.20: its T20 is much
  // shorter than the measurement's.
  room_reverb::CompareMeasurement::Request r;
  r.measurements_file = measurementsFile();
  r.room = roomMessage();
  room_reverb::AcousticMaterial absorbing;
  absorbing.name = "test_absorber";
  absorbing.absorption.assign(9, 0.5);
  absorbing.scattering.assign(9, 0.5);
  r.room.materials.push_back(absorbing);
  r.room.ceiling_material = "test_absorber";
  r.rays = 10000;
  r.duration_s = 1.2;
  r.out_dir = tempPath("compare_out").string();
  const auto response = compare(r);
  ASSERT_TRUE(response.success) << response.message;
  EXPECT_EQ(response.pairs, 2u);
  for (double band : {500.0, 1000.0, 2000.0}) EXPECT_LT(errorAt(response, "T20", band), -5.0) << band;
  EXPECT_GT(response.mean_abs_error_jnd, 2.0);
  const nlohmann::json j = nlohmann::json::parse(response.comparison_json);
  EXPECT_EQ(j["pairs"].size(), 2u);
  EXPECT_TRUE(std::filesystem::exists(r.out_dir + "/decay_curves.png"));

  // The model as measured: the mid-band T20 errors stay within the seed noise.
  r.room = roomMessage();
  r.out_dir.clear();
  const auto same = compare(r);
  ASSERT_TRUE(same.success) << same.message;
  for (double band : {500.0, 1000.0, 2000.0}) EXPECT_LT(std::abs(errorAt(same, "T20", band)), 2.0) << band;
}

TEST_F(EvaluationService, DiagnoseNamesMissingAirAndPublishesTheCorrectedRoom) {
  room_reverb::RoomModel corrected;
  bool received = false;
  ros::Subscriber sub = nh_.subscribe<room_reverb::RoomModel>("/evaluation/corrected_room", 1,
                                                              [&](const room_reverb::RoomModel::ConstPtr& m) {
                                                                corrected = *m;
                                                                received = true;
                                                              });
  room_reverb::DiagnoseRoom::Request r;
  r.measurements_file = measurementsFile();
  r.room = roomMessage();
  r.no_air = true;  // the model lacks air absorption; the measurement had it (30 %)
  r.causes = {"air_absorption", "scattering"};
  r.max_causes = 1;
  r.rays = 4000;
  r.duration_s = 1.0;
  r.out_dir = tempPath("diagnose_out").string();
  r.publish_correction = true;
  const auto response = diagnose(r);
  ASSERT_TRUE(response.success) << response.message;
  ASSERT_EQ(response.causes.size(), 1u) << response.diagnosis_json;
  EXPECT_EQ(response.causes[0].cause, "air_absorption");
  EXPECT_GT(response.causes[0].heldout_gain_jnd, response.noise_jnd);
  EXPECT_LT(response.causes[0].error_after_jnd, response.causes[0].error_before_jnd);
  ASSERT_TRUE(response.has_extended_room);
  EXPECT_TRUE(response.extended_room.air_absorption);
  EXPECT_NEAR(response.extended_room.humidity_percent, 30.0, 0.15 * 30.0);
  for (const char* file : {"/diagnosis.json", "/report.md", "/extended_room.yaml"}) {
    EXPECT_TRUE(std::filesystem::exists(r.out_dir + file)) << file;
  }
  const nlohmann::json j = nlohmann::json::parse(response.diagnosis_json);
  EXPECT_EQ(j["causes"][0]["cause"], "air_absorption");
  for (int i = 0; i < 50 && !received; ++i) {
    ros::spinOnce();
    ros::Duration(0.1).sleep();
  }
  ASSERT_TRUE(received) << "no corrected room on /evaluation/corrected_room";
  EXPECT_TRUE(corrected.air_absorption);
  EXPECT_EQ(corrected.header.frame_id, "room");
}

TEST_F(EvaluationService, LiveLoopPublishesTheCorrectedSceneForTheRenderer) {
  // A rig's measured RIR (with its positions) and the visual route's room model arrive on
  // topics; the node diagnoses in the background and publishes the room to hear.
  room_reverb::RoomScene scene;
  int received = 0;
  ros::Subscriber sub = nh_.subscribe<room_reverb::RoomScene>("/evaluation/corrected_scene", 5,
                                                              [&](const room_reverb::RoomScene::ConstPtr& m) {
                                                                scene = *m;
                                                                ++received;
                                                              });
  ros::Publisher room_pub = nh_.advertise<room_reverb::RoomModel>("/evaluation/room", 1, true);
  ros::Publisher rir_pub = nh_.advertise<room_reverb::ImpulseResponse>("/evaluation/impulse_response", 1, true);
  room_reverb::ImpulseResponse rir;
  rir.audio = ros_bridge::toMessage(core::readAudioFile(measuredRir("live.wav", kSource1, kReceiver1)), "ambix");
  rir.source_position.x = kSource1.x();
  rir.source_position.y = kSource1.y();
  rir.source_position.z = kSource1.z();
  rir.receiver_position.x = kReceiver1.x();
  rir.receiver_position.y = kReceiver1.y();
  rir.receiver_position.z = kReceiver1.z();
  rir.positions_known = true;
  room_reverb::RoomModel room = roomMessage();
  room.air_known = true;
  room.air_absorption = false;  // the visual route's model knows nothing of the air
  room_pub.publish(room);
  rir_pub.publish(rir);
  // A newer room model arrives while the first diagnosis runs (as the visual route
  // refines its model): the worker must diagnose again with it, not stop or crash.
  ros::Duration(1.0).sleep();
  room.surface_confidence.assign(6, 0.9);
  room_pub.publish(room);
  for (int i = 0; i < 3000 && received < 2; ++i) {
    ros::spinOnce();
    ros::Duration(0.1).sleep();
  }
  ASSERT_EQ(received, 2) << "expected a corrected scene for each room model within 300 s";
  EXPECT_NEAR(scene.source.x, kSource1.x(), 1e-9);
  EXPECT_NEAR(scene.listener.y, kReceiver1.y(), 1e-9);
  EXPECT_EQ(scene.mode, "accurate");
  EXPECT_DOUBLE_EQ(scene.room.size.x, 5.0);
  // The measured RIR decays faster at high frequencies than a room without air: the
  // correction puts the air back (the planted-effect tests check the fitted humidity).
  EXPECT_TRUE(scene.room.air_absorption);
}

TEST_F(EvaluationService, BadInputAnswersWithAReason) {
  room_reverb::CompareMeasurement::Request missing;
  missing.measurements_file = "/nonexistent/measurements.yaml";
  missing.room = roomMessage();
  auto a = compare(missing);
  EXPECT_FALSE(a.success);
  EXPECT_NE(a.message.find("/nonexistent/measurements.yaml"), std::string::npos) << a.message;

  room_reverb::CompareMeasurement::Request both;
  both.measurements_file = measurementsFile();
  both.room = roomMessage();
  both.mesh_file = "/tmp/room.obj";
  auto b = compare(both);
  EXPECT_FALSE(b.success);
  EXPECT_NE(b.message.find("not both"), std::string::npos) << b.message;

  room_reverb::CompareMeasurement::Request outside;
  outside.measurements_file = writeFile("outside.yaml", "pairs:\n  - {source_m: [9, 1, 1], receiver_m: [2, 2, 1]}\n"
                                                         "parameters: {bands_hz: [500], t20_s: [0.5]}\n");
  outside.room = roomMessage();
  outside.rays = 100;
  auto c = compare(outside);
  EXPECT_FALSE(c.success);
  EXPECT_NE(c.message.find("outside"), std::string::npos) << c.message;

  // Two channels said to be AmbiX.
  core::AudioBuffer stereo;
  stereo.channels.assign(2, std::vector<float>(4800, 0.0f));
  stereo.channels[0][10] = 1.0f;
  const std::string two = tempPath("two.wav").string();
  core::writeAudioFile(two, stereo);
  room_reverb::DiagnoseRoom::Request wrong;
  wrong.measurements_file = writeFile("two.yaml", "pairs:\n  - {file: " + two +
                                                      ", format: ambix, source_m: [1, 1, 1], receiver_m: [2, 2, 1]}\n");
  wrong.room = roomMessage();
  wrong.max_causes = -1;
  auto d = diagnose(wrong);
  EXPECT_FALSE(d.success);
  EXPECT_NE(d.message.find("channel"), std::string::npos) << d.message;
  EXPECT_TRUE(d.causes.empty());
}

// A second evaluation node (the binary next to this test's) under `name`, whose private
// parameters the caller has set on the master: its exit code and its error output.
std::pair<int, std::string> runEvaluationNode(const std::string& name) {
  const ToolRun run = runSiblingNode("evaluation", name, 20);
  return {run.exit_code, run.err};
}

TEST(EvaluationNode, AnUnknownOrMistypedCauseListStopsTheNodeWithOneLine) {
  ros::param::set("/evaluation_unknown_cause/causes", std::vector<std::string>{"air_absorption", "reverb_gremlins"});
  auto [code, output] = runEvaluationNode("evaluation_unknown_cause");
  EXPECT_NE(output.find("unknown cause 'reverb_gremlins'"), std::string::npos) << output;
  EXPECT_EQ(code, 2) << output;

  // One name where a list belongs: refused, not silently replaced by the whole catalogue.
  ros::param::set("/evaluation_cause_string/causes", std::string("air_absorption"));
  std::tie(code, output) = runEvaluationNode("evaluation_cause_string");
  EXPECT_NE(output.find("parameter ~causes must be a list of strings"), std::string::npos) << output;
  EXPECT_EQ(code, 2) << output;

  // A number given as text is refused too.
  ros::param::set("/evaluation_rays_string/diagnosis_rays", std::string("many"));
  std::tie(code, output) = runEvaluationNode("evaluation_rays_string");
  EXPECT_NE(output.find("parameter ~diagnosis_rays must be an integer"), std::string::npos) << output;
  EXPECT_EQ(code, 2) << output;

  // As is any parameter of another type than its own (typedParam): a flag given as text.
  ros::param::set("/evaluation_flag_string/auto_diagnose", std::string("yes"));
  std::tie(code, output) = runEvaluationNode("evaluation_flag_string");
  EXPECT_NE(output.find("parameter ~auto_diagnose must be true or false"), std::string::npos) << output;
  EXPECT_EQ(code, 2) << output;
}

}  // namespace
}  // namespace room_reverb::test

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_evaluation_service");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
