#include "room_reverb/ros/room_conversions.h"
#include "room_reverb/ros/sample_bag.h"

#include <geometry_msgs/QuaternionStamped.h>
#include <rosbag/bag.h>
#include <room_reverb/ImpulseResponse.h>
#include <std_msgs/String.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/audio/channel_mix.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/image_conversions.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/synthetic_capture/capture_scene.h"

namespace room_reverb::ros_bridge {

namespace {

namespace fs = std::filesystem;

// A fixed start time: the same inputs give the same bag.
const ::ros::Time kStart(1700000000, 0);
constexpr double kHeadPeriodS = 10.0;
constexpr double kHeadAmplitudeRad = 30.0 * M_PI / 180.0;

core::MeasurementPair rigPair(const std::string& measurement_path) {
  const core::Measurements m = core::loadMeasurements(measurement_path);
  if (m.pairs.size() != 1) throw core::InputError(measurement_path + ": the sample room needs exactly one pair");
  return m.pairs.front();
}

std::string describe(const SampleBagOptions& o, const core::MeasurementPair& pair) {
  std::ostringstream os;
  os << "room_reverb sample capture bag. GENERATED, not recorded: the images are rendered by the capture "
        "generator from "
     << o.room_dir << "/visible.yaml; the 'measured' B-format RIR is the accurate simulation (" << o.rays
     << " rays) of " << o.room_dir
     << "/acoustic.yaml, which differs from what the cameras see: parquet floor under a rug (carpet in the images), "
        "a cabinet hidden behind the sofa, air at 24 degC / 35 %. Source at ("
     << pair.source_m.transpose() << ") m, microphone at the rig (" << pair.receiver_m.transpose()
     << ") m, room frame. Dry source: " << fs::path(o.dry_source).filename().string()
     << ". Head: +-30 degrees yaw, 10 s period.";
  return os.str();
}

}  // namespace

SampleBagReport writeSampleBag(const SampleBagOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  if (!(o.duration_s > 0.0 && o.duration_s <= 60.0)) throw core::InputError("sample bag: duration must be in (0, 60] s");
  if (o.chunk_frames < 64) throw core::InputError("sample bag: chunks of at least 64 frames");
  core::createFolder(o.out_dir);
  const core::MaterialLibrary library = core::MaterialLibrary::loadDefault();

  // What the cameras see.
  core::CaptureScene visible = core::loadCaptureScene(o.room_dir + "/visible.yaml");
  if (o.width > 0) visible.options.width = o.width;
  visible.options.fisheye = true;
  visible.options.fisheye_calibration = core::loadDualFisheyeCalibration(core::defaultDualFisheyeCalibrationPath());
  const core::StereoCapture capture = core::renderCapture(visible.room, library, visible.options);

  // What the microphone hears.
  const core::RoomModel acoustic = core::loadRoomModel(o.room_dir + "/acoustic.yaml");
  const core::MeasurementPair pair = rigPair(o.room_dir + "/measurement.yaml");
  core::SimulationSettings settings;
  settings.mode = core::SimulationMode::kAccurate;
  settings.air = acoustic.air;
  settings.rays.ray_count = o.rays;
  const core::SimulationResult rir =
      core::simulateRoom(core::roomModelToScene(acoustic, library), pair.source_m, pair.receiver_m, settings);
  const std::string rir_path = (fs::path(o.out_dir) / "measured_rir.wav").string();
  core::writeAudioFile(rir_path, rir.impulse_response, core::SampleEncoding::kFloat32);
  {
    std::ofstream yaml((fs::path(o.out_dir) / "measurement.yaml").string());
    yaml << "# The sample room's simulated 'measurement' (see " << o.room_dir << "/acoustic.yaml).\n"
         << "room: " << fs::absolute(o.room_dir + "/acoustic.yaml").string() << "\n"
         << "pairs:\n  - {file: measured_rir.wav, format: ambix, source_m: [" << pair.source_m.x() << ", "
         << pair.source_m.y() << ", " << pair.source_m.z() << "], receiver_m: [" << pair.receiver_m.x() << ", "
         << pair.receiver_m.y() << ", " << pair.receiver_m.z() << "]}\n";
  }

  const core::AudioBuffer dry = core::mixToMono(core::readAudioFile(o.dry_source));

  SampleBagReport report;
  report.bag_path = (fs::path(o.out_dir) / "sample.bag").string();
  rosbag::Bag bag;
  try {
    bag.open(report.bag_path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);
  } catch (const rosbag::BagException& e) {
    throw core::InputError(report.bag_path + ": " + e.what());
  }

  std_msgs::String info;
  info.data = describe(o, pair);
  bag.write("/sample_bag/info", kStart, info);

  const ::ros::Time capture_time = kStart + ::ros::Duration(0.5);
  std_msgs::Header image_header;
  image_header.stamp = capture_time;
  image_header.frame_id = "rig";
  bag.write("/rig/top/image_raw", capture_time, imageToMessage(capture.top.fisheye, "bgr8", image_header));
  bag.write("/rig/bottom/image_raw", capture_time, imageToMessage(capture.bottom.fisheye, "bgr8", image_header));

  room_reverb::ImpulseResponse ir;
  ir.audio = toMessage(rir.impulse_response, "ambix");
  ir.audio.header.stamp = capture_time;
  ir.audio.header.frame_id = "rig";  // the microphone's frame: the RSAO's directions are in it
  ir.source_position = toPoint(pair.source_m);
  ir.receiver_position = toPoint(pair.receiver_m);
  ir.positions_known = true;
  bag.write("/rig/impulse_response", capture_time, ir);

  // The dry source in real time, looped, and the head turning.
  const std::size_t total = static_cast<std::size_t>(std::llround(o.duration_s * dry.sample_rate_hz));
  const std::vector<float>& samples = dry.channels.front();
  for (std::size_t first = 0; first < total; first += static_cast<std::size_t>(o.chunk_frames)) {
    core::AudioBuffer chunk = core::makeSilentBuffer(1, std::min<std::size_t>(o.chunk_frames, total - first), dry.sample_rate_hz);
    for (std::size_t n = 0; n < chunk.frameCount(); ++n) chunk.channels[0][n] = samples[(first + n) % samples.size()];
    room_reverb::AudioBuffer msg = toMessage(chunk, "mono");
    const ::ros::Time t = kStart + ::ros::Duration(static_cast<double>(first) / dry.sample_rate_hz);
    msg.header.stamp = t;
    bag.write("/source/audio", t, msg);
  }
  for (double s = 0.0; s < o.duration_s; s += 0.05) {
    const double yaw = kHeadAmplitudeRad * std::sin(2.0 * M_PI * s / kHeadPeriodS);
    geometry_msgs::QuaternionStamped head;
    head.header.stamp = kStart + ::ros::Duration(s);
    head.header.frame_id = "head";
    head.quaternion.z = std::sin(0.5 * yaw);
    head.quaternion.w = std::cos(0.5 * yaw);
    bag.write("/head_orientation", head.header.stamp, head);
  }
  bag.close();
  report.bag_megabytes = static_cast<double>(fs::file_size(report.bag_path)) / 1e6;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace room_reverb::ros_bridge
