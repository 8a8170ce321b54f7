// rostest: the EstimateRsao service of rsao_estimator, called as another robot would, and
// what it publishes (the latched estimate and the rviz markers).
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <room_reverb/EstimateRsao.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <string>

#include "room_reverb/audio/audio_file.h"
#include "room_reverb/ros/audio_conversions.h"

namespace {

const std::string kRir = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/rirs/bformat/dixon_studio_theatre_r1.wav";

class RsaoService : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(ros::service::waitForService("/rsao_estimator/estimate", ros::Duration(30.0)));
    client_ = nh_.serviceClient<room_reverb::EstimateRsao>("/rsao_estimator/estimate");
  }

  room_reverb::EstimateRsao::Response call(const room_reverb::EstimateRsao::Request& r) {
    room_reverb::EstimateRsao srv;
    srv.request = r;
    EXPECT_TRUE(client_.call(srv));
    return srv.response;
  }

  room_reverb::EstimateRsao::Request fromMessage(const room_reverb::core::AudioBuffer& audio,
                                                const std::string& layout) {
    room_reverb::EstimateRsao::Request r;
    r.impulse_response.audio = room_reverb::ros_bridge::toMessage(audio, layout);
    r.impulse_response.audio.header.frame_id = "rig";
    return r;
  }

  void expectRefused(const room_reverb::EstimateRsao::Request& r, const std::string& fragment) {
    const auto response = call(r);
    EXPECT_FALSE(response.success);
    EXPECT_NE(response.message.find(fragment), std::string::npos) << response.message;
    EXPECT_TRUE(response.rsao.reflections.empty());
  }

  ros::NodeHandle nh_;
  ros::ServiceClient client_;
};

TEST_F(RsaoService, FileAndMessageGiveTheSameObjectAndItIsPublished) {
  room_reverb::EstimateRsao::Request by_file;
  by_file.file = kRir;
  by_file.format = "fuma";
  const auto from_file = call(by_file);
  ASSERT_TRUE(from_file.success) << from_file.message;
  ASSERT_GE(from_file.rsao.reflections.size(), 2u);
  EXPECT_EQ(from_file.rsao.late.t60_s.size(), 9u);
  EXPECT_EQ(from_file.rsao.header.frame_id, "rig");
  // The Dixon studio theatre: T60 about 1 s in the mid bands.
  EXPECT_NEAR(from_file.rsao.late.t60_s[4], 1.07, 0.1);
  // Two slopes where the decay bends (its 8 kHz band), one entry per band for all.
  const room_reverb::LateReverb& late = from_file.rsao.late;
  ASSERT_EQ(late.second_share.size(), 9u);
  ASSERT_EQ(late.first_decay_constant_per_s.size(), 9u);
  ASSERT_EQ(late.second_decay_constant_per_s.size(), 9u);
  int bent = 0;
  for (std::size_t b = 0; b < 9; ++b) {
    if (late.second_share[b] <= 0.0) continue;
    ++bent;
    EXPECT_LT(late.second_share[b], 1.0);
    EXPECT_GT(late.first_decay_constant_per_s[b], late.second_decay_constant_per_s[b]);
  }
  EXPECT_GE(bent, 1);

  const auto from_message = call(fromMessage(room_reverb::core::readAudioFile(kRir), "fuma"));
  ASSERT_TRUE(from_message.success) << from_message.message;
  ASSERT_EQ(from_message.rsao.reflections.size(), from_file.rsao.reflections.size());
  for (std::size_t k = 0; k < from_file.rsao.reflections.size(); ++k) {
    EXPECT_DOUBLE_EQ(from_message.rsao.reflections[k].time_of_arrival_s, from_file.rsao.reflections[k].time_of_arrival_s);
  }

  // The last estimate stays on ~rsao (latched), drawn on ~markers: a sphere and a label
  // per reflection after a DELETEALL.
  const auto published = ros::topic::waitForMessage<room_reverb::Rsao>("/rsao_estimator/rsao", nh_, ros::Duration(5.0));
  ASSERT_TRUE(published);
  EXPECT_EQ(published->reflections.size(), from_message.rsao.reflections.size());
  const auto markers =
      ros::topic::waitForMessage<visualization_msgs::MarkerArray>("/rsao_estimator/markers", nh_, ros::Duration(5.0));
  ASSERT_TRUE(markers);
  EXPECT_EQ(markers->markers.size(), 1 + 2 * from_message.rsao.reflections.size());
  const auto& direct = markers->markers[1];
  const double radius = std::sqrt(direct.pose.position.x * direct.pose.position.x +
                                  direct.pose.position.y * direct.pose.position.y +
                                  direct.pose.position.z * direct.pose.position.z);
  EXPECT_NEAR(radius, from_message.rsao.reflections[0].distance_m, 1e-6);

  // Each reflection: its image source at its distance along its direction, a confidence.
  for (const auto& r : from_message.rsao.reflections) {
    const auto& p = r.image_source;
    EXPECT_NEAR(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), r.distance_m, 1e-9);
    EXPECT_NEAR(std::atan2(p.y, p.x), r.azimuth_rad, 1e-9);
    EXPECT_GE(r.confidence, 0.0);
    EXPECT_LE(r.confidence, 1.0);
  }
  EXPECT_GT(from_message.rsao.reflections[0].confidence, 0.8);  // a direct sound alone in its window

  // With the measurement's positions, the direct sound's distance is theirs (1 m here,
  // whatever the file's pre-delay) and every image source moves with it.
  auto positioned = fromMessage(room_reverb::core::readAudioFile(kRir), "fuma");
  positioned.impulse_response.positions_known = true;
  positioned.impulse_response.source_position.x = 1.0;
  const auto placed = call(positioned);
  ASSERT_TRUE(placed.success) << placed.message;
  EXPECT_NEAR(placed.rsao.reflections[0].distance_m, 1.0, 1e-9);
  for (std::size_t k = 1; k < placed.rsao.reflections.size(); ++k) {
    EXPECT_NEAR(placed.rsao.reflections[k].distance_m - from_message.rsao.reflections[k].distance_m,
                1.0 - from_message.rsao.reflections[0].distance_m, 1e-9);
  }
}

TEST_F(RsaoService, AnImpulseResponseOnTheTopicIsEstimatedAndPublished) {
  // As a bag replay or the rig's measurement node delivers it.
  ros::Publisher publisher = nh_.advertise<room_reverb::ImpulseResponse>("/rsao_estimator/impulse_response", 1, true);
  room_reverb::ImpulseResponse message;
  room_reverb::core::AudioBuffer rir = room_reverb::core::readAudioFile(kRir);
  for (auto& channel : rir.channels) channel.resize(48000);  // a distinct object: 1 s of it
  message.audio = room_reverb::ros_bridge::toMessage(rir, "fuma");
  message.audio.header.frame_id = "rig_from_topic";
  publisher.publish(message);
  const ros::Time deadline = ros::Time::now() + ros::Duration(20.0);
  room_reverb::Rsao::ConstPtr published;
  while (ros::Time::now() < deadline) {
    published = ros::topic::waitForMessage<room_reverb::Rsao>("/rsao_estimator/rsao", nh_, ros::Duration(1.0));
    if (published && published->header.frame_id == "rig_from_topic") break;
  }
  ASSERT_TRUE(published);
  EXPECT_EQ(published->header.frame_id, "rig_from_topic");
  EXPECT_GE(published->reflections.size(), 2u);
}

TEST_F(RsaoService, PerCallOverrides) {
  room_reverb::EstimateRsao::Request r;
  r.file = kRir;
  r.format = "fuma";
  r.max_reflections = 2;
  r.mixing_time_s = 0.08;
  const auto response = call(r);
  ASSERT_TRUE(response.success) << response.message;
  EXPECT_LE(response.rsao.reflections.size(), 3u);
  EXPECT_DOUBLE_EQ(response.rsao.late.mixing_time_s, 0.08);
}

TEST_F(RsaoService, BadInputIsRefusedWithAReason) {
  room_reverb::EstimateRsao::Request missing;
  missing.file = "/nonexistent/rir.wav";
  missing.format = "fuma";
  expectRefused(missing, "no such file");

  room_reverb::EstimateRsao::Request no_format;
  no_format.file = kRir;
  expectRefused(no_format, "format is required");

  const room_reverb::core::AudioBuffer rir = room_reverb::core::readAudioFile(kRir);
  expectRefused(fromMessage(rir, "binaural"), "B-format convention is unknown");

  room_reverb::core::AudioBuffer mono = rir;
  mono.channels.resize(1);
  expectRefused(fromMessage(mono, "ambix"), "4 channels");

  room_reverb::core::AudioBuffer silent = room_reverb::core::makeSilentBuffer(4, 48000, 48000.0);
  expectRefused(fromMessage(silent, "ambix"), "silent");

  room_reverb::core::AudioBuffer nan = rir;
  nan.channels[1][500] = std::nanf("");
  expectRefused(fromMessage(nan, "fuma"), "NaN");

  room_reverb::core::AudioBuffer short_rir = rir;
  for (auto& c : short_rir.channels) c.resize(2400);
  expectRefused(fromMessage(short_rir, "fuma"), "too short");

  room_reverb::EstimateRsao::Request negative;
  negative.file = kRir;
  negative.format = "fuma";
  negative.lpc_order = -3;
  expectRefused(negative, "must not be negative");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_rsao_service");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
