// binaural_renderer: a dry source (~source_file looped, or ~source) heard in the current
// room (~rsao, ~impulse_response, ~room_scene via the simulator, or ~room_file), turned
// with the listener's head (~head_orientation), streamed as binaural chunks on ~binaural
// in real time; ~status reports the stream, ~render_to_file renders offline. Parameters:
// config/binaural_renderer.yaml.
#include <ros/ros.h>

#include "room_reverb/ros/binaural_renderer_server.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "binaural_renderer");
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  try {
    room_reverb::ros_bridge::BinauralRendererServer server(nh, private_nh);
    // Callbacks prepare rooms (a resynthesis, a simulator call) while others keep coming:
    // two callback threads, the audio thread apart.
    ros::AsyncSpinner spinner(2);
    spinner.start();
    server.start();
    ros::waitForShutdown();
    server.stop();
  } catch (const std::exception& e) {
    ROS_FATAL("binaural_renderer: %s", e.what());
    return 2;
  }
  return 0;
}
