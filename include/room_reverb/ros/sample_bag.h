#pragma once
// The sample capture bag of the demo and the replay tests: what a rig in the sample room
// (data/sample_room/) would record. No real room has both a licensed 360° stereo capture and
// a B-format RIR, so the room is generated: its images by the capture generator from
// visible.yaml, its "measured" RIR by the accurate simulation of acoustic.yaml, which holds
// what cameras cannot see (another floor, a hidden cabinet, other air). The bag says so on
// /sample_bag/info.
//
// Topics (frame ids in brackets):
//   /rig/top/image_raw, /rig/bottom/image_raw  sensor_msgs/Image bgr8 dual fisheye [rig], once
//   /rig/impulse_response    room_reverb/ImpulseResponse, AmbiX order 1, 48 kHz [room], once
//   /source/audio            room_reverb/AudioBuffer mono chunks of the dry source, real time
//   /head_orientation        geometry_msgs/QuaternionStamped [head], 20 Hz, the head turning
//                            slowly left and right (+-30 degrees, 10 s period)
//   /sample_bag/info         std_msgs/String, what the bag holds and how it was made
#include <string>

namespace room_reverb::ros_bridge {

struct SampleBagOptions {
  std::string room_dir;        // data/sample_room (visible.yaml, acoustic.yaml, measurement.yaml)
  std::string dry_source;      // mono or multichannel WAV (mixed to mono), any rate
  std::string out_dir;         // written: sample.bag, measured_rir.wav, measurement.yaml
  double duration_s = 10.0;    // of the audio and head track
  int width = 0;               // equirect width of the capture (the fisheye is W x W/2); 0: visible.yaml's
  int rays = 100000;           // of the RIR simulation
  int chunk_frames = 1024;     // samples per /source/audio message
};

struct SampleBagReport {
  std::string bag_path;
  double bag_megabytes = 0.0;
  double seconds = 0.0;
};

// InputError for missing or malformed inputs, a duration outside (0, 60] s, an output folder
// that cannot be written.
SampleBagReport writeSampleBag(const SampleBagOptions& options);

}  // namespace room_reverb::ros_bridge
