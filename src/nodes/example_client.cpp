// example_client: how another robot uses a running room_reverb system. Asks
// <ns>/rsao_estimator/estimate for the RSAO of a B-format RIR file and
// <ns>/room_simulator/simulate for the impulse response of a room model, and prints what
// came back (and writes the simulated RIR with --out). Usage:
//   rosrun room_reverb example_client --rir FILE --format fuma|ambix
//       --room ROOM.yaml --source X Y Z --listener X Y Z [--mode accurate|fast|eyring] [--ns rig]
//       [--out IR.wav]
// Exit status: 0 both answered, 1 a service failed or is missing, 2 bad arguments.
#include <ros/ros.h>
#include <room_reverb/EstimateRsao.h>
#include <room_reverb/SimulateRoom.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/common/error.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/room_conversions.h"

namespace {

geometry_msgs::Point point(const std::vector<std::string>& a, std::size_t at) {
  geometry_msgs::Point p;
  p.x = std::stod(a.at(at));
  p.y = std::stod(a.at(at + 1));
  p.z = std::stod(a.at(at + 2));
  return p;
}

int usage(const std::string& why) {
  std::cerr << "example_client: " << why
            << "\nusage: example_client --rir FILE --format fuma|ambix --room ROOM.yaml --source X Y Z --listener X Y Z"
               " [--mode accurate|fast|eyring] [--ns rig] [--out IR.wav]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "example_client", ros::init_options::AnonymousName);
  const std::vector<std::string> a(argv + 1, argv + argc);
  std::map<std::string, std::size_t> at;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].rfind("--", 0) == 0) at[a[i].substr(2)] = i + 1;
  }
  for (const char* key : {"rir", "format", "room", "source", "listener"}) {
    if (!at.count(key)) return usage(std::string("--") + key + " is required");
  }
  const std::string ns = at.count("ns") ? a.at(at["ns"]) : "rig";
  room_reverb::EstimateRsao estimate;
  room_reverb::SimulateRoom simulate;
  try {
    // The node runs in its own working folder: send an absolute path.
    estimate.request.file = std::filesystem::absolute(a.at(at["rir"])).string();
    estimate.request.format = a.at(at["format"]);
    simulate.request.room = room_reverb::ros_bridge::toMessage(room_reverb::core::loadRoomModel(a.at(at["room"])));
    simulate.request.source = point(a, at["source"]);
    simulate.request.listener = point(a, at["listener"]);
    simulate.request.mode = at.count("mode") ? a.at(at["mode"]) : "accurate";
    simulate.request.global_scattering = -1.0;  // the materials' own scattering (0 would override it)
  } catch (const std::exception& e) {
    return usage(e.what());
  }

  const std::string rsao_service = "/" + ns + "/rsao_estimator/estimate";
  if (!ros::service::waitForService(rsao_service, ros::Duration(10.0)) || !ros::service::call(rsao_service, estimate)) {
    std::cerr << "example_client: " << rsao_service << " is not answering\n";
    return 1;
  }
  if (!estimate.response.success) {
    std::cerr << "example_client: RSAO refused: " << estimate.response.message << "\n";
    return 1;
  }
  std::cout << "RSAO: " << estimate.response.rsao.reflections.size() << " arrivals (direct sound first)\n";
  for (const auto& r : estimate.response.rsao.reflections) {
    std::cout << "  toa " << r.time_of_arrival_s * 1000.0 << " ms, level " << r.level << ", azimuth " << r.azimuth_rad * 57.29578
              << " deg, elevation " << r.elevation_rad * 57.29578 << " deg\n";
  }

  const std::string sim_service = "/" + ns + "/room_simulator/simulate";
  if (!ros::service::waitForService(sim_service, ros::Duration(10.0)) && !ros::service::exists(sim_service, true)) {
    std::cerr << "example_client: " << sim_service << " is not offered\n";
    return 1;
  }
  if (!ros::service::call(sim_service, simulate)) {
    std::cerr << "example_client: the call to " << sim_service << " failed\n";
    return 1;
  }
  if (!simulate.response.success) {
    std::cerr << "example_client: simulation refused: " << simulate.response.message << "\n";
    return 1;
  }
  std::cout << "simulated (" << simulate.request.mode << "): " << simulate.response.impulse_response.audio.channel_count
            << " channels; T30 per octave [s]:";
  for (const double t : simulate.response.t30_s) std::cout << " " << t;
  std::cout << "\n";
  if (at.count("out")) {
    try {
      room_reverb::core::writeAudioFile(a.at(at["out"]),
                                        room_reverb::ros_bridge::fromMessage(simulate.response.impulse_response.audio),
                                        room_reverb::core::SampleEncoding::kFloat32);
      std::cout << "wrote " << a.at(at["out"]) << "\n";
    } catch (const room_reverb::core::InputError& e) {
      std::cerr << "example_client: " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}
