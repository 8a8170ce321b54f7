// make_sample_bag: writes the sample capture bag (ros/sample_bag.h) with the RIR and
// measurement file next to it. Usage (scripts/make-sample-bag runs it):
//   make_sample_bag OUT_DIR [ROOM_DIR [DRY_WAV]]
// Exit status: 0 written, 2 bad input (one line on stderr).
#include <ros/time.h>

#include <iostream>
#include <string>

#include "room_reverb/common/error.h"
#include "room_reverb/ros/sample_bag.h"

int main(int argc, char** argv) {
  if (argc < 2 || argc > 4) {
    std::cerr << "usage: make_sample_bag OUT_DIR [ROOM_DIR [DRY_WAV]]\n";
    return 2;
  }
  ros::Time::init();
  const std::string source_dir = ROOM_REVERB_SOURCE_DIR;
  room_reverb::ros_bridge::SampleBagOptions options;
  options.out_dir = argv[1];
  options.room_dir = argc > 2 ? argv[2] : source_dir + "/data/sample_room";
  options.dry_source = argc > 3 ? argv[3] : source_dir + "/data/dry/speech.wav";
  try {
    const auto report = room_reverb::ros_bridge::writeSampleBag(options);
    std::cout << "wrote " << report.bag_path << " (" << report.bag_megabytes << " MB) in " << report.seconds << " s\n";
  } catch (const room_reverb::core::InputError& e) {
    std::cerr << "make_sample_bag: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
