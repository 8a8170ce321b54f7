// rostest: the SimulateRoom service of room_simulator, called as another robot would.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <room_reverb/SimulateRoom.h>

#include <cmath>

#include "tool_run.h"

namespace {

room_reverb::RoomModel shoebox() {
  room_reverb::RoomModel room;
  room.header.frame_id = "room";
  room.size.x = 6.0;
  room.size.y = 4.0;
  room.size.z = 3.0;
  room.has_ceiling = true;
  room.floor_material = "parquet_on_concrete";
  room.ceiling_material = "acoustic_ceiling_tiles";
  room.wall_x_min_material = room.wall_x_max_material = "plaster_smooth";
  room.wall_y_min_material = room.wall_y_max_material = "plaster_smooth";
  room_reverb::Cuboid table;
  table.label = "table";
  table.material = "wood_panel";
  table.center.x = 3.0;
  table.center.y = 2.0;
  table.center.z = 0.37;
  table.size.x = 1.6;
  table.size.y = 0.8;
  table.size.z = 0.74;
  table.confidence = 1.0;
  room.objects.push_back(table);
  return room;
}

room_reverb::SimulateRoom::Request request() {
  room_reverb::SimulateRoom::Request r;
  r.room = shoebox();
  r.source.x = 1.5;
  r.source.y = 1.2;
  r.source.z = 1.4;
  r.listener.x = 4.6;
  r.listener.y = 2.9;
  r.listener.z = 1.6;
  r.rays = 4000;
  r.duration_s = 1.0;
  r.global_scattering = -1.0;
  return r;
}

class SimulationService : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(ros::service::waitForService("/room_simulator/simulate", ros::Duration(30.0)));
    client_ = nh_.serviceClient<room_reverb::SimulateRoom>("/room_simulator/simulate");
  }

  room_reverb::SimulateRoom::Response call(const room_reverb::SimulateRoom::Request& r) {
    room_reverb::SimulateRoom srv;
    srv.request = r;
    EXPECT_TRUE(client_.call(srv));
    return srv.response;
  }

  void expectFailure(const room_reverb::SimulateRoom::Request& r, const std::string& fragment) {
    const auto response = call(r);
    EXPECT_FALSE(response.success);
    EXPECT_NE(response.message.find(fragment), std::string::npos) << response.message;
    EXPECT_TRUE(response.impulse_response.audio.samples.empty());
  }

  ros::NodeHandle nh_;
  ros::ServiceClient client_;
};

TEST_F(SimulationService, SimulatesARoomModelWithFurniture) {
  // An inline material, absorption 0.2 and scattering 0.5 in every band, on every face: a
  // diffuse field, where Eyring holds. (With the absorbing ceiling alone T30 is twice
  // Eyring's, as grazing waves between the hard walls live long; and with absorption that
  // steps from one octave to the next, the analysis filters blend neighbouring decays.)
  auto r = request();
  room_reverb::AcousticMaterial wall;
  wall.name = "test_wall";
  wall.absorption.assign(9, 0.2);
  wall.scattering.assign(9, 0.5);
  r.room.materials.push_back(wall);
  r.room.floor_material = r.room.ceiling_material = r.room.wall_x_min_material = r.room.wall_x_max_material =
      r.room.wall_y_min_material = r.room.wall_y_max_material = "test_wall";
  const auto response = call(r);
  ASSERT_TRUE(response.success) << response.message;
  const auto& audio = response.impulse_response.audio;
  EXPECT_EQ(audio.channel_count, 4u);  // first-order AmbiX, the node's default
  EXPECT_EQ(audio.channel_layout, "ambix");
  EXPECT_DOUBLE_EQ(audio.sample_rate_hz, 48000.0);
  EXPECT_EQ(audio.samples.size(), 4u * 48000u);
  EXPECT_EQ(audio.header.frame_id, "room");
  EXPECT_EQ(response.rays_traced, 4000u);
  // A closed box: leaks only from rays that graze an edge exactly (about 1 in 10^4).
  EXPECT_LE(response.leaked_rays, response.rays_traced / 1000);
  ASSERT_EQ(response.t30_s.size(), 9u);
  ASSERT_EQ(response.eyring_t60_s.size(), 9u);
  // Mid bands: the simulated T30 near Eyring's (few rays, so a loose bound; the engine's
  // own tests hold it to 10 %).
  for (std::size_t b = 2; b <= 6; ++b) {
    ASSERT_TRUE(std::isfinite(response.t30_s[b])) << b;
    EXPECT_NEAR(response.t30_s[b] / response.eyring_t60_s[b], 1.0, 0.25) << b;
  }
}

TEST_F(SimulationService, FastAndEyringModesAndSecondOrderOnRequest) {
  auto r = request();
  r.mode = "fast";
  r.rays = 3000;  // the fast mode's rays
  r.ambisonic_order = 2;
  const auto fast = call(r);
  ASSERT_TRUE(fast.success) << fast.message;
  EXPECT_EQ(fast.impulse_response.audio.channel_count, 9u);
  EXPECT_EQ(fast.rays_traced, 3000u);
  r.mode = "eyring";
  const auto eyring = call(r);
  ASSERT_TRUE(eyring.success) << eyring.message;
  EXPECT_EQ(eyring.rays_traced, 0u);
}

TEST_F(SimulationService, BadInputAnswersWithAReason) {
  auto unknown = request();
  unknown.room.floor_material = "marshmallow";
  expectFailure(unknown, "marshmallow");

  auto outside = request();
  outside.source.x = 7.0;
  expectFailure(outside, "outside");

  auto in_table = request();
  in_table.source.x = 3.0;
  in_table.source.y = 2.0;
  in_table.source.z = 0.3;
  expectFailure(in_table, "is inside object 0 (table)");

  auto bad_absorption = request();
  room_reverb::AcousticMaterial m;
  m.name = "bad_panel";
  m.absorption.assign(9, 0.3);
  m.absorption[4] = 1.5;
  m.scattering.assign(9, 0.1);
  bad_absorption.room.materials.push_back(m);
  bad_absorption.room.wall_x_min_material = "bad_panel";
  expectFailure(bad_absorption, "bad_panel");

  auto short_bands = request();
  m.absorption.assign(5, 0.3);
  short_bands.room.materials = {m};
  expectFailure(short_bands, "9 values");

  auto no_mesh = request();
  no_mesh.mesh_file = "/nonexistent/room.obj";
  expectFailure(no_mesh, "/nonexistent/room.obj");

  auto negative_rays = request();
  negative_rays.rays = -5;
  expectFailure(negative_rays, "negative");
  auto too_many_rays = request();
  too_many_rays.rays = 2000000000;
  expectFailure(too_many_rays, "more than this node's ~max_rays (10000000)");

  auto flat = request();
  flat.room.size.z = 0.0;
  expectFailure(flat, "size");

  auto nan_listener = request();
  nan_listener.listener.y = std::nan("");
  expectFailure(nan_listener, "");

  auto wrong_frame = request();
  wrong_frame.room.header.frame_id = "map";
  expectFailure(wrong_frame, "frame");

  auto bad_mode = request();
  bad_mode.mode = "quantum";
  expectFailure(bad_mode, "quantum");
}

// The fast mode's parameters out of range stop a second simulator node with one line.
TEST(RoomSimulatorNode, FastModeParametersOutOfRangeStopItWithOneLine) {
  ros::param::set("/simulator_bad_mixture/fast_launch_mixture", 1.5);
  using room_reverb::test::runSiblingNode;
  room_reverb::test::ToolRun run = runSiblingNode("room_simulator", "simulator_bad_mixture", 20);
  EXPECT_NE(run.err.find("parameter ~fast_launch_mixture must be a share from 0 to 0.9"), std::string::npos) << run.err;
  EXPECT_EQ(run.exit_code, 2) << run.err;
  ros::param::set("/simulator_bad_track/fast_track_radius", 0.0);
  run = runSiblingNode("room_simulator", "simulator_bad_track", 20);
  EXPECT_NE(run.err.find("parameter ~fast_track_radius must be a positive number of metres"), std::string::npos) << run.err;
  EXPECT_EQ(run.exit_code, 2) << run.err;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_simulation_service");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
