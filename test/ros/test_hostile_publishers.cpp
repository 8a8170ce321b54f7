// rostest: every subscribed topic of every node gets what a broken driver or a stranger
// might send: NaN and infinite samples, poses and quaternions; empty, malformed and large
// buffers; wrong channel counts, layouts and encodings; images of the wrong size or
// encoding; point clouds with no points, all-NaN points or fields outside the point;
// messages out of order in time. Afterwards every node must still answer a service (its
// own with an invalid request, or dynamic_reconfigure's, which a callback that hangs would
// block; and roscpp's ~set_logger_level), and must have said what it refused: a warning or
// an error on /rosout, or a counter on the renderer's ~status.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/QuaternionStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <room_reverb/AudioBuffer.h>
#include <room_reverb/BuildRoomModel.h>
#include <room_reverb/CompareMeasurement.h>
#include <room_reverb/EstimateRsao.h>
#include <room_reverb/ImpulseResponse.h>
#include <room_reverb/RenderToFile.h>
#include <room_reverb/RoomModel.h>
#include <room_reverb/RoomScene.h>
#include <room_reverb/Rsao.h>
#include <room_reverb/SimulateRoom.h>
#include <room_reverb/StreamStatus.h>
#include <roscpp/SetLoggerLevel.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Warnings and errors on /rosout, counted by the node that logged them.
class RosoutLog {
 public:
  explicit RosoutLog(ros::NodeHandle& nh) : sub_(nh.subscribe("/rosout", 1000, &RosoutLog::onLog, this)) {}

  int count(const std::string& node) {
    std::lock_guard<std::mutex> lock(mutex_);
    return static_cast<int>(lines_[node].size());
  }

  std::string lines(const std::string& node) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string all;
    for (const std::string& line : lines_[node]) all += "  " + line + "\n";
    return all;
  }

 private:
  void onLog(const rosgraph_msgs::Log::ConstPtr& log) {
    if (log->level < rosgraph_msgs::Log::WARN) return;
    std::lock_guard<std::mutex> lock(mutex_);
    lines_[log->name].push_back(log->msg);
  }

  std::mutex mutex_;
  std::map<std::string, std::vector<std::string>> lines_;
  ros::Subscriber sub_;
};

// Spins until `done` or `timeout_s`; true if `done`.
bool waitUntil(const std::function<bool()>& done, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::WallTime::now() < end) {
    ros::spinOnce();
    if (done()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return done();
}

// Publishes each message once a subscriber is connected, paced so that a queue of one
// (and the time pairing's queue of two) sees every message.
template <typename Message>
void publishAll(ros::NodeHandle& nh, const std::string& topic, const std::vector<Message>& messages,
                double pause_s = 0.03) {
  ros::Publisher pub = nh.advertise<Message>(topic, 100);
  ASSERT_TRUE(waitUntil([&] { return pub.getNumSubscribers() > 0; }, 20.0)) << "nobody subscribes " << topic;
  for (const Message& m : messages) {
    pub.publish(m);
    ros::WallDuration(pause_s).sleep();
  }
  ros::WallDuration(0.2).sleep();  // let the last ones leave before the publisher goes
}

// As publishAll, for a subscriber whose queue holds one message (the latest room wins):
// each message waits until `handled()` (the node's count of what it took or refused) has
// moved, so that none is replaced unread when the node is slow.
template <typename Message>
void publishEach(ros::NodeHandle& nh, const std::string& topic, const std::vector<Message>& messages,
                 const std::function<std::uint64_t()>& handled) {
  ros::Publisher pub = nh.advertise<Message>(topic, 100);
  ASSERT_TRUE(waitUntil([&] { return pub.getNumSubscribers() > 0; }, 20.0)) << "nobody subscribes " << topic;
  for (const Message& m : messages) {
    const std::uint64_t before = handled();
    pub.publish(m);
    EXPECT_TRUE(waitUntil([&] { return handled() > before; }, 10.0)) << topic << ": a message was not handled";
  }
}

// --- what a broken driver sends -------------------------------------------------------

std_msgs::Header stampedAt(double t_s) {
  std_msgs::Header h;
  h.stamp = ros::Time(t_s);
  h.frame_id = "rig";
  return h;
}

sensor_msgs::Image image(std::uint32_t width, std::uint32_t height, const std::string& encoding,
                         std::uint32_t bytes_per_px, std::size_t data_bytes, std::uint8_t value = 128) {
  sensor_msgs::Image m;
  m.width = width;
  m.height = height;
  m.encoding = encoding;
  m.step = width * bytes_per_px;
  m.data.assign(data_bytes, value);
  return m;
}

sensor_msgs::Image fullImage(std::uint32_t width, std::uint32_t height, const std::string& encoding,
                             std::uint32_t bytes_per_px, std::uint8_t value = 128) {
  return image(width, height, encoding, bytes_per_px, static_cast<std::size_t>(width) * height * bytes_per_px, value);
}

// The first pairs of hostileImagePairs(): malformed messages, refused before any image
// processing.
constexpr int kMalformedImagePairs = 7;

// Top and bottom images that a camera pair might send, each pair a (top, bottom).
std::vector<std::pair<sensor_msgs::Image, sensor_msgs::Image>> hostileImagePairs() {
  std::vector<std::pair<sensor_msgs::Image, sensor_msgs::Image>> pairs;
  const auto both = [&](const sensor_msgs::Image& m) { pairs.emplace_back(m, m); };
  both(image(0, 0, "bgr8", 3, 0));                                 // empty
  both(image(128, 64, "bgr8", 3, 10));                             // fewer bytes than it claims
  both(image(4000000, 2000000, "bgr8", 3, 100));                   // a huge size, no data
  sensor_msgs::Image short_step = fullImage(128, 64, "bgr8", 3);
  short_step.step = 128;                                           // rows shorter than the pixels
  both(short_step);
  both(fullImage(128, 64, "32FC1", 4));                            // not a camera encoding
  both(fullImage(128, 64, "yuv422", 2));
  both(fullImage(128, 64, "", 3));
  both(fullImage(100, 100, "bgr8", 3));                            // not 2:1
  both(fullImage(2, 1, "mono8", 1));                               // 2:1, tiny
  both(fullImage(256, 128, "bgr8", 3, 0));                         // black
  both(fullImage(256, 128, "bgr8", 3, 255));                       // saturated
  pairs.emplace_back(fullImage(256, 128, "bgr8", 3), fullImage(128, 64, "bgr8", 3));   // sizes differ
  pairs.emplace_back(fullImage(128, 64, "bgr8", 3), fullImage(128, 64, "mono8", 1));   // types differ
  both(fullImage(1024, 512, "mono8", 1, 90));                      // large, flat: nothing to match or level
  return pairs;
}

// Publishes the pairs on top and bottom, each pair at one stamp, the stamps going back in time.
void publishImagePairs(ros::NodeHandle& nh, const std::string& top, const std::string& bottom) {
  std::vector<sensor_msgs::Image> tops, bottoms;
  double t = 1000.0;
  for (auto [a, b] : hostileImagePairs()) {
    a.header = b.header = stampedAt(t);
    t -= 1.0;
    tops.push_back(a);
    bottoms.push_back(b);
  }
  ros::Publisher top_pub = nh.advertise<sensor_msgs::Image>(top, 100);
  ros::Publisher bottom_pub = nh.advertise<sensor_msgs::Image>(bottom, 100);
  ASSERT_TRUE(waitUntil([&] { return top_pub.getNumSubscribers() > 0 && bottom_pub.getNumSubscribers() > 0; }, 20.0))
      << "nobody subscribes " << top << " and " << bottom;
  for (std::size_t k = 0; k < tops.size(); ++k) {
    top_pub.publish(tops[k]);
    bottom_pub.publish(bottoms[k]);
    ros::WallDuration(0.1).sleep();
  }
  ros::WallDuration(0.2).sleep();
}

geometry_msgs::Quaternion quaternion(double x, double y, double z, double w) {
  geometry_msgs::Quaternion q;
  q.x = x;
  q.y = y;
  q.z = z;
  q.w = w;
  return q;
}

std::vector<geometry_msgs::Quaternion> hostileQuaternions() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  return {quaternion(nan, 0, 0, 1), quaternion(0, 0, 0, inf), quaternion(0, 0, 0, 0), quaternion(2, 0, 0, 0),
          quaternion(1e308, 1e308, 1e308, 1e308), quaternion(0, 0, 0, -inf)};
}

// Listener poses: every hostile orientation at a sound position, and positions that are
// not numbers at a sound orientation.
std::vector<geometry_msgs::PoseStamped> hostilePoses() {
  std::vector<geometry_msgs::PoseStamped> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  double t = 400.0;
  for (const auto& q : hostileQuaternions()) {
    geometry_msgs::PoseStamped m;
    m.header = stampedAt(t -= 1.0);
    m.pose.position.x = m.pose.position.y = m.pose.position.z = 1.0;
    m.pose.orientation = q;
    out.push_back(m);
  }
  for (const double bad : {nan, inf, -inf}) {
    geometry_msgs::PoseStamped m;
    m.header = stampedAt(t -= 1.0);
    m.pose.position.x = 1.0;
    m.pose.position.y = bad;
    m.pose.orientation.w = 1.0;
    out.push_back(m);
  }
  return out;
}

std::vector<geometry_msgs::QuaternionStamped> hostileStampedQuaternions() {
  std::vector<geometry_msgs::QuaternionStamped> out;
  double t = 500.0;
  for (const auto& q : hostileQuaternions()) {
    geometry_msgs::QuaternionStamped m;
    m.header = stampedAt(t -= 1.0);  // back in time
    m.quaternion = q;
    out.push_back(m);
  }
  return out;
}

std::vector<sensor_msgs::Imu> hostileImu() {
  std::vector<sensor_msgs::Imu> out;
  double t = 500.0;
  for (const auto& q : hostileQuaternions()) {
    sensor_msgs::Imu m;
    m.header = stampedAt(t -= 1.0);
    m.orientation = q;
    m.orientation_covariance[0] = 0.01;
    out.push_back(m);
  }
  return out;
}

room_reverb::AudioBuffer audio(std::uint32_t channels, std::size_t samples, const std::string& layout,
                               double rate_hz = 48000.0, float value = 0.0f) {
  room_reverb::AudioBuffer m;
  m.sample_rate_hz = rate_hz;
  m.channel_count = channels;
  m.channel_layout = layout;
  m.samples.assign(samples, value);
  if (!m.samples.empty()) m.samples[0] = 1.0f;  // an impulse, where the value leaves one
  return m;
}

// Audio as a broken driver or a stranger sends it, in `layout` where the buffer is sound.
std::vector<room_reverb::AudioBuffer> hostileAudio(const std::string& layout, std::uint32_t channels) {
  std::vector<room_reverb::AudioBuffer> out;
  room_reverb::AudioBuffer nan = audio(channels, 4800 * channels, layout);
  nan.samples[7] = kNaN;
  out.push_back(nan);
  room_reverb::AudioBuffer inf = audio(channels, 4800 * channels, layout);
  inf.samples[9] = -kInf;
  out.push_back(inf);
  out.push_back(audio(channels, 0, layout));                                  // empty
  out.push_back(audio(0, 480, layout));                                       // no channels
  out.push_back(audio(channels, 4800 * channels + 1, layout));                // not whole frames
  out.push_back(audio(channels, 4800 * channels, layout, 0.0));               // no rate
  out.push_back(audio(channels, 4800 * channels, layout, -48000.0));
  out.push_back(audio(channels, 4800 * channels, layout, std::numeric_limits<double>::quiet_NaN()));
  out.push_back(audio(channels, 4800 * channels, layout, 1e12));
  out.push_back(audio(channels, 480 * channels, layout, 1e-3));              // 480 frames would be days at 48 kHz
  out.push_back(audio(3, 4800 * 3, "fuma"));                                  // wrong channel counts
  out.push_back(audio(5, 4800 * 5, "ambix"));
  out.push_back(audio(2, 4800 * 2, "mono"));
  out.push_back(audio(2, 4800 * 2, "binaural"));                              // layouts no room has
  out.push_back(audio(4, 4800 * 4, ""));
  out.push_back(audio(4, 4800 * 4, "fuma\n\x1b[31mX"));
  out.push_back(audio(200, 200 * 100, layout));                               // 200 channels
  // Large, in a layout no room has; last, as a queue of one would drop a message that came
  // while it is still being read.
  out.push_back(audio(channels, 2000000 * channels, "stereo"));
  return out;
}

std::vector<room_reverb::ImpulseResponse> hostileImpulseResponses() {
  std::vector<room_reverb::ImpulseResponse> out(1);
  out[0].audio = audio(4, 4800 * 4, "fuma");  // sound, without positions
  for (const room_reverb::AudioBuffer& a : hostileAudio("fuma", 4)) {
    room_reverb::ImpulseResponse m;
    m.audio = a;
    m.positions_known = true;
    m.source_position.x = std::numeric_limits<double>::quiet_NaN();
    m.receiver_position.y = std::numeric_limits<double>::infinity();
    out.push_back(m);
  }
  return out;
}

room_reverb::Rsao rsaoWithOneReflection() {
  room_reverb::Rsao m;
  m.sample_rate_hz = 48000.0;
  m.duration_s = 0.5;
  room_reverb::EarlyReflection r;
  r.level = 1.0;
  r.lpc = {1.0};
  r.lpc_gain = 1.0;
  m.reflections.push_back(r);
  return m;
}

std::vector<room_reverb::Rsao> hostileRsaos() {
  std::vector<room_reverb::Rsao> out;
  out.push_back(room_reverb::Rsao());                                   // no reflections
  room_reverb::Rsao m = rsaoWithOneReflection();
  m.reflections[0].sos = {1.0, 0.0};                                    // not whole sections
  out.push_back(m);
  m = rsaoWithOneReflection();
  m.reflections[0].level = std::numeric_limits<double>::quiet_NaN();
  out.push_back(m);
  m = rsaoWithOneReflection();
  m.reflections[0].time_of_arrival_s = std::numeric_limits<double>::infinity();
  out.push_back(m);
  m = rsaoWithOneReflection();
  m.duration_s = 1e9;                                                   // a response of 30 years
  out.push_back(m);
  m = rsaoWithOneReflection();
  m.sample_rate_hz = 0.0;
  out.push_back(m);
  m = rsaoWithOneReflection();
  m.late.center_hz = {1000.0};                                          // band arrays of different lengths
  out.push_back(m);
  m = rsaoWithOneReflection();
  m.late.center_hz = {1000.0};
  m.late.decay_constant_per_s = {std::numeric_limits<double>::quiet_NaN()};
  m.late.t60_s = {-1.0};
  m.late.level = {1e300};
  m.late.onset_level = {0.0};
  m.late.reliable = {true};
  m.late.reason = {""};
  out.push_back(m);
  m = rsaoWithOneReflection();
  m.late.second_share = {0.5};                                          // two slopes of bands that are not there
  m.late.first_decay_constant_per_s = {-3.0};
  out.push_back(m);
  return out;
}

room_reverb::RoomModel roomOfSize(double x, double y, double z) {
  room_reverb::RoomModel m;
  m.header.frame_id = "room";
  m.size.x = x;
  m.size.y = y;
  m.size.z = z;
  m.has_ceiling = true;
  for (std::string* face : {&m.floor_material, &m.ceiling_material, &m.wall_x_min_material, &m.wall_x_max_material,
                            &m.wall_y_min_material, &m.wall_y_max_material}) {
    *face = "concrete";
  }
  return m;
}

std::vector<room_reverb::RoomModel> hostileRooms() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<room_reverb::RoomModel> out{roomOfSize(nan, 3, 3), roomOfSize(4, nan, 3), roomOfSize(4, 3, -1),
                                          roomOfSize(1e300, 1e300, 1e300), roomOfSize(4, 3, 0), room_reverb::RoomModel()};
  room_reverb::RoomModel wrong_frame = roomOfSize(4, 3, 3);
  wrong_frame.header.frame_id = "map";
  out.push_back(wrong_frame);
  room_reverb::RoomModel no_material = roomOfSize(4, 3, 3);
  no_material.floor_material = "unobtainium";
  out.push_back(no_material);
  room_reverb::RoomModel bad_object = roomOfSize(4, 3, 3);
  room_reverb::Cuboid object;
  object.material = "concrete";
  object.center.x = nan;
  object.size.x = object.size.y = object.size.z = 1.0;
  bad_object.objects.push_back(object);
  out.push_back(bad_object);
  room_reverb::RoomModel bad_confidence = roomOfSize(4, 3, 3);
  bad_confidence.surface_confidence = {1.0, 2.0};
  out.push_back(bad_confidence);
  room_reverb::RoomModel short_relief = roomOfSize(4, 3, 3);
  short_relief.surface_relief_scattering = {0.1, 0.2};
  out.push_back(short_relief);
  room_reverb::RoomModel relief_out_of_range = roomOfSize(4, 3, 3);
  relief_out_of_range.surface_relief_scattering.assign(54, 1.5);
  out.push_back(relief_out_of_range);
  return out;
}

std::vector<room_reverb::RoomScene> hostileRoomScenes() {
  std::vector<room_reverb::RoomScene> out;
  for (const room_reverb::RoomModel& room : hostileRooms()) {
    room_reverb::RoomScene m;
    m.room = room;
    m.source.x = m.source.y = m.source.z = 1.0;
    m.listener.x = m.listener.y = m.listener.z = 2.0;
    out.push_back(m);
  }
  room_reverb::RoomScene nan_source;
  nan_source.room = roomOfSize(4, 3, 3);
  nan_source.source.x = std::numeric_limits<double>::quiet_NaN();
  out.push_back(nan_source);
  room_reverb::RoomScene bad_mode = nan_source;
  bad_mode.source.x = 1.0;
  bad_mode.mode = "warp";
  out.push_back(bad_mode);
  return out;
}

// An XYZ float32 cloud of `points` (x, y, z each).
sensor_msgs::PointCloud2 cloud(const std::vector<std::array<float, 3>>& points) {
  sensor_msgs::PointCloud2 m;
  m.header = stampedAt(100.0);
  m.height = 1;
  m.width = static_cast<std::uint32_t>(points.size());
  for (const char* name : {"x", "y", "z"}) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = static_cast<std::uint32_t>(4 * m.fields.size());
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    m.fields.push_back(f);
  }
  m.point_step = 12;
  m.row_step = m.point_step * m.width;
  m.data.resize(m.row_step);
  std::memcpy(m.data.data(), points.data(), m.data.size());
  return m;
}

// The clouds below whose structure is broken (the six after the first three and before
// the last): refused on arrival.
constexpr std::size_t kMalformedClouds = 6;

std::vector<sensor_msgs::PointCloud2> hostileClouds() {
  std::vector<sensor_msgs::PointCloud2> out;
  out.push_back(cloud({}));                                                            // no points
  out.push_back(cloud(std::vector<std::array<float, 3>>(5000, {kNaN, kNaN, kNaN})));   // all NaN
  out.push_back(cloud(std::vector<std::array<float, 3>>(5000, {kInf, 1.0f, 1.0f})));
  sensor_msgs::PointCloud2 m = cloud(std::vector<std::array<float, 3>>(100, {1.0f, 1.0f, 1.0f}));
  m.fields.pop_back();                                                                // no z
  out.push_back(m);
  m = cloud(std::vector<std::array<float, 3>>(100, {1.0f, 1.0f, 1.0f}));
  m.fields[0].datatype = sensor_msgs::PointField::UINT8;                              // x not a float
  out.push_back(m);
  m = cloud(std::vector<std::array<float, 3>>(100, {1.0f, 1.0f, 1.0f}));
  m.fields[2].offset = 0xfffffffeu;                                                   // z far outside the point
  out.push_back(m);
  m = cloud(std::vector<std::array<float, 3>>(100, {1.0f, 1.0f, 1.0f}));
  m.width = 0xffffffffu;                                                              // more points than bytes
  m.height = 0xffffffffu;
  out.push_back(m);
  m = cloud(std::vector<std::array<float, 3>>(100, {1.0f, 1.0f, 1.0f}));
  m.point_step = 0;
  m.row_step = 0;
  out.push_back(m);
  m = cloud(std::vector<std::array<float, 3>>(100, {1.0f, 1.0f, 1.0f}));
  m.is_bigendian = true;
  out.push_back(m);
  m = cloud(std::vector<std::array<float, 3>>(100, {1.0f, 1.0f, 1.0f}));
  m.header.frame_id = "map";                                                          // not the rig frame
  out.push_back(m);
  return out;
}

// --- is the node still there ----------------------------------------------------------

// Calls `service` with `srv`; true if it answered (whatever it answered).
template <typename Service>
bool answers(const std::string& service, Service& srv) {
  return ros::service::waitForService(service, ros::Duration(5.0)) && ros::service::call(service, srv);
}

// roscpp's ~set_logger_level (logger "ros" at "info", the default): the process is alive
// and registered. It is served by roscpp's internal queue, so the tests below also call a
// service of the node's own where it has one, which a callback that hangs would block.
// (Not ~get_loggers: it segfaults the node in Debian's rosconsole with log4cxx.)
bool answersSetLoggerLevel(const std::string& node) {
  roscpp::SetLoggerLevel srv;
  srv.request.logger = "ros";
  srv.request.level = "info";
  return answers(node + "/set_logger_level", srv);
}

const std::vector<std::string> kNodes{"/ci/capture_ingest", "/sd/spherical_depth", "/sdn/room_reverb_manager",
                                      "/rm/room_model",     "/rs/rsao_estimator",  "/sim/room_simulator",
                                      "/br/binaural_renderer", "/ev/evaluation"};

class HostilePublishers : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nh_ = std::make_unique<ros::NodeHandle>();
    log_ = std::make_unique<RosoutLog>(*nh_);
    for (const std::string& node : kNodes) {
      ASSERT_TRUE(ros::service::waitForService(node + "/set_logger_level", ros::Duration(30.0))) << node << " never started";
    }
    // The subscription to /rosout reaches every node before anything is sent.
    ros::WallDuration(1.0).sleep();
  }
  static void TearDownTestSuite() {
    log_.reset();
    nh_.reset();
  }

  // Waits until `node` has logged at least `n` warnings or errors; prints what it logged.
  static void expectWarnings(const std::string& node, int n) {
    EXPECT_TRUE(waitUntil([&] { return log_->count(node) >= n; }, 10.0))
        << node << " logged " << log_->count(node) << " warnings, expected at least " << n << ":\n"
        << log_->lines(node);
  }

  static std::unique_ptr<ros::NodeHandle> nh_;
  static std::unique_ptr<RosoutLog> log_;
};

std::unique_ptr<ros::NodeHandle> HostilePublishers::nh_;
std::unique_ptr<RosoutLog> HostilePublishers::log_;

TEST_F(HostilePublishers, CaptureIngestRefusesBadImagesAndImu) {
  publishAll(*nh_, "/ci/imu", hostileImu());
  publishImagePairs(*nh_, "/ci/top/image_raw", "/ci/bottom/image_raw");
  // Every pair; the well-formed ones because no usable IMU orientation came.
  expectWarnings("/ci/capture_ingest", static_cast<int>(hostileImagePairs().size()));
  EXPECT_TRUE(answersSetLoggerLevel("/ci/capture_ingest"));
}

TEST_F(HostilePublishers, SphericalDepthNodeAndNodeletRefuseBadImages) {
  publishImagePairs(*nh_, "/sd/top/image_equirect", "/sd/bottom/image_equirect");
  publishImagePairs(*nh_, "/sdn/top/image_equirect", "/sdn/bottom/image_equirect");
  // Every pair but the flat grey one, which is a valid image pair (with no depth to find).
  const int refused = static_cast<int>(hostileImagePairs().size()) - 1;
  expectWarnings("/sd/spherical_depth", refused);
  expectWarnings("/sdn/room_reverb_manager", refused);
  // An empty reconfiguration changes nothing and is answered from the callback queue.
  for (const std::string node : {"/sd/spherical_depth", "/sdn/spherical_depth"}) {
    dynamic_reconfigure::Reconfigure reconfigure;
    EXPECT_TRUE(answers(node + "/set_parameters", reconfigure)) << node;
  }
  EXPECT_TRUE(answersSetLoggerLevel("/sd/spherical_depth"));
  EXPECT_TRUE(answersSetLoggerLevel("/sdn/room_reverb_manager"));
}

TEST_F(HostilePublishers, RoomModelRefusesBadCloudsImagesAndTilts) {
  publishAll(*nh_, "/rm/rig_tilt", hostileStampedQuaternions());
  std::vector<sensor_msgs::Image> images;
  for (const auto& pair : hostileImagePairs()) images.push_back(pair.first);
  publishAll(*nh_, "/rm/top/image_equirect", images);
  publishAll(*nh_, "/rm/points", hostileClouds(), 0.2);
  // Every bad tilt, malformed image and cloud: a malformed cloud is refused on arrival
  // (one line), a well-formed one that holds no usable room fails its build (two: the
  // build's reason and the node's note that the build on the new cloud failed).
  expectWarnings("/rm/room_model", static_cast<int>(hostileQuaternions().size() + kMalformedImagePairs +
                                                    2 * hostileClouds().size() - kMalformedClouds));
  const std::string lines = log_->lines("/rm/room_model");
  std::size_t kept = 0;
  for (std::size_t at = lines.find("the last good cloud stays"); at != std::string::npos;
       at = lines.find("the last good cloud stays", at + 1)) {
    ++kept;
  }
  EXPECT_EQ(kept, kMalformedClouds) << lines;
  room_reverb::BuildRoomModel build;
  ASSERT_TRUE(answers("/rm/room_model/build", build));
  EXPECT_FALSE(build.response.success);
  EXPECT_FALSE(build.response.message.empty());
  EXPECT_TRUE(answersSetLoggerLevel("/rm/room_model"));
}

TEST_F(HostilePublishers, RsaoEstimatorRefusesBadImpulseResponses) {
  const auto rirs = hostileImpulseResponses();
  publishAll(*nh_, "/rs/rsao_estimator/impulse_response", rirs, 0.1);
  expectWarnings("/rs/rsao_estimator", static_cast<int>(rirs.size()));
  room_reverb::EstimateRsao estimate;
  ASSERT_TRUE(answers("/rs/rsao_estimator/estimate", estimate));
  EXPECT_FALSE(estimate.response.success);
  EXPECT_TRUE(answersSetLoggerLevel("/rs/rsao_estimator"));
}

TEST_F(HostilePublishers, BinauralRendererRefusesBadRoomsSourcesAndHeads) {
  room_reverb::StreamStatus status;
  int statuses = 0;
  ros::Subscriber status_sub = nh_->subscribe<room_reverb::StreamStatus>(
      "/br/binaural_renderer/status", 10, [&](const room_reverb::StreamStatus::ConstPtr& m) {
        status = *m;
        ++statuses;
      });
  publishAll(*nh_, "/br/binaural_renderer/source", hostileAudio("mono", 1));
  publishAll(*nh_, "/br/binaural_renderer/head_orientation", hostileStampedQuaternions());
  publishAll(*nh_, "/br/binaural_renderer/listener_pose", hostilePoses());
  // Room models to walk in: refused with a warning each (its queue holds the latest one).
  publishAll(*nh_, "/br/binaural_renderer/room_model", hostileRooms(), 0.3);
  // Rooms: each one taken or refused (~status counts both) before the next.
  ASSERT_TRUE(waitUntil([&] { return statuses > 0; }, 10.0)) << "no ~status";
  const auto rooms_handled = [&] { return status.room_changes + status.rooms_rejected; };
  const auto rirs = hostileImpulseResponses();
  publishEach(*nh_, "/br/binaural_renderer/impulse_response", rirs, rooms_handled);
  const auto rsaos = hostileRsaos();
  publishEach(*nh_, "/br/binaural_renderer/rsao", rsaos, rooms_handled);
  const auto scenes = hostileRoomScenes();
  publishEach(*nh_, "/br/binaural_renderer/room_scene", scenes, rooms_handled);

  // The renderer counts what it refused on ~status. Played, not refused: the RIR without
  // positions (the renderer needs none) and the RSAO whose sample_rate_hz is 0 (the
  // resynthesis works at its own rate).
  const std::size_t rooms_sound_enough = 2;
  const std::size_t rooms = rirs.size() + rsaos.size() + scenes.size() - rooms_sound_enough;
  const std::size_t orientations = hostileQuaternions().size() + hostilePoses().size();
  const bool counted = waitUntil(
      [&] {
        return statuses > 0 && status.rooms_rejected >= rooms && status.orientations_rejected >= orientations &&
               status.non_finite_samples > 0;
      },
      15.0);
  EXPECT_TRUE(counted) << "rooms_rejected " << status.rooms_rejected << " (of " << rooms << "), orientations_rejected "
                       << status.orientations_rejected << " (of " << orientations << "), non_finite_samples "
                       << status.non_finite_samples << ", last: " << status.last_message;
  expectWarnings("/br/binaural_renderer", static_cast<int>(rooms));
  room_reverb::RenderToFile render;
  ASSERT_TRUE(answers("/br/binaural_renderer/render_to_file", render));
  EXPECT_FALSE(render.response.success);
  EXPECT_TRUE(answersSetLoggerLevel("/br/binaural_renderer"));
  room_reverb::SimulateRoom simulate;
  ASSERT_TRUE(answers("/sim/room_simulator/simulate", simulate));
  EXPECT_FALSE(simulate.response.success);
  EXPECT_TRUE(answersSetLoggerLevel("/sim/room_simulator"));
}

// A publisher gone wild: head orientations as fast as the test can send them and source
// audio at several times real time, for three seconds. The renderer keeps its own pace: it
// streams about as much audio as time passes, discards (and counts) the source it cannot
// play instead of queueing it without bound, takes every orientation, and still answers.
TEST_F(HostilePublishers, BinauralRendererKeepsItsPaceUnderAFlood) {
  room_reverb::StreamStatus status;
  int statuses = 0;
  std::size_t frames = 0;
  ros::Subscriber status_sub = nh_->subscribe<room_reverb::StreamStatus>(
      "/br/binaural_renderer/status", 10, [&](const room_reverb::StreamStatus::ConstPtr& m) {
        status = *m;
        ++statuses;
      });
  ros::Subscriber stream_sub = nh_->subscribe<room_reverb::AudioBuffer>(
      "/br/binaural_renderer/binaural", 200, [&](const room_reverb::AudioBuffer::ConstPtr& m) {
        if (m->channel_count > 0) frames += m->samples.size() / m->channel_count;
      });
  ros::Publisher head = nh_->advertise<geometry_msgs::QuaternionStamped>("/br/binaural_renderer/head_orientation", 1000);
  ros::Publisher source = nh_->advertise<room_reverb::AudioBuffer>("/br/binaural_renderer/source", 1000);
  ASSERT_TRUE(waitUntil([&] { return head.getNumSubscribers() > 0 && source.getNumSubscribers() > 0 && statuses > 0; },
                        20.0));
  ASSERT_TRUE(waitUntil([&] { return frames > 0; }, 10.0)) << "the renderer streams nothing";
  // The pace is judged by the renderer's own account between two of its statuses: every
  // chunk due in that time is published or, where it fell more than ~max_lag_s behind,
  // counted as dropped. (What reaches this test's subscriber depends on this process being
  // scheduled too: on shared test machines a three-second flood once took eight.)
  const int statuses_before = statuses;
  ASSERT_TRUE(waitUntil([&] { return statuses > statuses_before; }, 5.0));
  const room_reverb::StreamStatus before = status;
  const std::uint64_t overflow_before = status.source_overflow_samples;
  const std::uint64_t rejected_before = status.orientations_rejected;
  const std::size_t frames_before = frames;

  const room_reverb::AudioBuffer chunk = audio(1, 1024, "mono", 48000.0, 0.1f);
  const ros::WallTime start = ros::WallTime::now();
  int orientations = 0, chunks = 0;
  while ((ros::WallTime::now() - start).toSec() < 3.0) {
    geometry_msgs::QuaternionStamped q;
    q.header.stamp = ros::Time::now();
    const double yaw = 0.001 * orientations;
    q.quaternion = quaternion(0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw));
    head.publish(q);
    if (++orientations % 5 == 0) {
      source.publish(chunk);
      ++chunks;
    }
    ros::spinOnce();
    ros::WallDuration(0.0002).sleep();
  }
  const double flooded_s = (ros::WallTime::now() - start).toSec();
  const int statuses_after = statuses;
  ASSERT_TRUE(waitUntil([&] { return statuses >= statuses_after + 2; }, 10.0));  // two more of its accounts
  const double status_span_s = (status.header.stamp - before.header.stamp).toSec();
  const double paced_s = static_cast<double>((status.chunks_published - before.chunks_published) +
                                             (status.chunks_dropped - before.chunks_dropped)) *
                         status.chunk_frames / status.sample_rate_hz;
  const double streamed_s = static_cast<double>(frames - frames_before) / 48000.0;
  const double source_s = chunks * 1024 / 48000.0;
  std::printf("[ stats    ] flood: %d orientations (%.0f per s), %.1f s of source in %.1f s; %.1f s streamed; "
              "%.1f s of chunks published or dropped in %.1f s between statuses; overflow %llu samples\n",
              orientations, orientations / flooded_s, source_s, flooded_s, streamed_s, paced_s, status_span_s,
              static_cast<unsigned long long>(status.source_overflow_samples - overflow_before));
  ASSERT_GT(source_s, 2.0 * flooded_s) << "the test could not flood: nothing is shown";
  EXPECT_GT(paced_s, 0.7 * status_span_s);
  EXPECT_LT(paced_s, status_span_s + 1.0);
  EXPECT_GT(streamed_s, 0.5) << "the stream does not reach its subscribers";
  EXPECT_GT(status.source_overflow_samples, overflow_before);
  EXPECT_EQ(status.orientations_rejected, rejected_before);
  EXPECT_TRUE(answersSetLoggerLevel("/br/binaural_renderer"));
}

TEST_F(HostilePublishers, EvaluationRefusesBadRoomsAndImpulseResponses) {
  const auto rooms = hostileRooms();
  const auto rirs = hostileImpulseResponses();
  publishAll(*nh_, "/ev/evaluation/room", rooms, 0.05);
  publishAll(*nh_, "/ev/evaluation/impulse_response", rirs, 0.1);
  expectWarnings("/ev/evaluation", static_cast<int>(rooms.size() + rirs.size()));
  room_reverb::CompareMeasurement compare;
  ASSERT_TRUE(answers("/ev/evaluation/compare", compare));
  EXPECT_FALSE(compare.response.success);
  EXPECT_TRUE(answersSetLoggerLevel("/ev/evaluation"));
}

// Last (tests run in the order written): after every barrage, every node still answers.
TEST_F(HostilePublishers, EveryNodeStillAnswersAtTheEnd) {
  for (const std::string& node : kNodes) EXPECT_TRUE(answersSetLoggerLevel(node)) << node << " does not answer";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_hostile_publishers");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
