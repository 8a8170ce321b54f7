// rostest: the ComputeMetrics service of metrics_node, called as another robot would.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <room_reverb/ComputeMetrics.h>

#include <cmath>
#include <limits>

#include "room_reverb/ros/audio_conversions.h"
#include "synthetic_rir.h"

namespace {

room_reverb::ComputeMetrics::Request requestFor(const std::vector<float>& samples, double rate = 48000.0,
                                                uint32_t channels = 1) {
  room_reverb::ComputeMetrics::Request request;
  request.impulse_response.audio.sample_rate_hz = rate;
  request.impulse_response.audio.channel_count = channels;
  request.impulse_response.audio.channel_layout = "mono";
  request.impulse_response.audio.samples = samples;
  return request;
}

class MetricsService : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(ros::service::waitForService("/metrics_node/compute_metrics", ros::Duration(30.0)));
    client_ = nh_.serviceClient<room_reverb::ComputeMetrics>("/metrics_node/compute_metrics");
  }

  room_reverb::ComputeMetrics::Response call(room_reverb::ComputeMetrics::Request request) {
    room_reverb::ComputeMetrics srv;
    srv.request = std::move(request);
    EXPECT_TRUE(client_.call(srv));
    return srv.response;
  }

  void expectFailure(const room_reverb::ComputeMetrics::Request& request, const std::string& fragment) {
    const auto response = call(request);
    EXPECT_FALSE(response.success);
    EXPECT_NE(response.message.find(fragment), std::string::npos) << response.message;
    EXPECT_TRUE(response.bands.empty());
  }

  ros::NodeHandle nh_;
  ros::ServiceClient client_;
};

}  // namespace

TEST_F(MetricsService, MeasuresAPlantedDecay) {
  const auto response = call(requestFor(room_reverb::test::exponentialDecayNoise(48000, 0.5, 480, 51)));
  ASSERT_TRUE(response.success) << response.message;
  EXPECT_NEAR(response.onset_s, 0.01, 1e-3);
  ASSERT_EQ(response.bands.size(), 9u);
  EXPECT_NEAR(response.broadband.t30_s, 0.5, 0.01);
  EXPECT_NEAR(response.bands[4].t20_s, 0.5, 0.02);
  EXPECT_TRUE(response.broadband.reliable);
}

TEST_F(MetricsService, ThirdOctaveBandsOnRequest) {
  auto request = requestFor(room_reverb::test::exponentialDecayNoise(48000, 0.5, 480, 52));
  request.bands = "third";
  const auto response = call(request);
  ASSERT_TRUE(response.success) << response.message;
  EXPECT_EQ(response.bands.size(), 31u);
}

TEST_F(MetricsService, UnmeasurableValuesAreNanWithAReason) {
  std::vector<float> rir = room_reverb::test::exponentialDecayNoise(48000, 0.5, 480, 53);
  room_reverb::test::addNoiseFloor(rir, -30.0, 54);
  const auto response = call(requestFor(rir));
  ASSERT_TRUE(response.success) << response.message;
  EXPECT_TRUE(std::isnan(response.broadband.t30_s));
  EXPECT_FALSE(response.broadband.reliable);
  EXPECT_NE(response.broadband.reason.find("T30"), std::string::npos);
}

TEST_F(MetricsService, BadInputAnswersSuccessFalse) {
  expectFailure(requestFor({}), "no samples");
  expectFailure(requestFor({0.5f}), "at least 10 ms");
  expectFailure(requestFor(std::vector<float>(48000, 0.0f)), "silent");
  std::vector<float> nan = room_reverb::test::exponentialDecayNoise(4800, 0.3, 10, 55);
  nan[7] = std::numeric_limits<float>::quiet_NaN();
  expectFailure(requestFor(nan), "NaN");
  nan[7] = std::numeric_limits<float>::infinity();
  expectFailure(requestFor(nan), "infinite");
  const std::vector<float> ok = room_reverb::test::exponentialDecayNoise(4800, 0.3, 10, 56);
  expectFailure(requestFor(ok, 0.0), "sample rate");
  expectFailure(requestFor(ok, 1e9), "sample rate");
  expectFailure(requestFor(ok, 48000.0, 0), "channel_count 0");
  expectFailure(requestFor(std::vector<float>(4801, 0.1f), 48000.0, 2), "not a multiple");
  auto wrong_channel = requestFor(ok);
  wrong_channel.channel = 2;
  expectFailure(wrong_channel, "channel 2 does not exist");
  auto wrong_bands = requestFor(ok);
  wrong_bands.bands = "fifth";
  expectFailure(wrong_bands, "unknown band resolution");
  // The node is still alive and answering after all of that.
  EXPECT_TRUE(call(requestFor(ok)).success);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_metrics_service");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
