// binaural_renderer: a dry source (~source_file looped, or ~source) heard in the current
// room (~rsao, ~impulse_response, ~room_scene via the simulator, or ~room_file), turned
// with the listener's head (~head_orientation), streamed as binaural chunks on ~binaural
// in real time; ~status reports the stream, ~render_to_file renders offline. Parameters:
// config/binaural_renderer.yaml.
#include <malloc.h>
#include <ros/ros.h>

#include "room_reverb/ros/binaural_renderer_server.h"

int main(int argc, char** argv) {
  // One malloc arena. With glibc's per-thread arenas the memory of swapped-out rooms stays
  // mapped: over 10 minutes with a new room every 5 s resident memory grows from 91 to
  // 247 MiB and still rises; with one arena it is reused, and it ends at 193 MiB, falling
  // (scripts/soak; docs/reliability.md), with the same late chunks and CPU share.
  mallopt(M_ARENA_MAX, 1);
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
