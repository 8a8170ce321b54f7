// The dual-fisheye calibration reader (dual_fisheye.h), on text in memory.
#include "fuzz_common.h"
#include "room_reverb/vision/dual_fisheye.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  room_reverb_fuzz::expectCleanRejection([&] {
    room_reverb::core::parseDualFisheyeCalibration(room_reverb_fuzz::text(data, size), "fuzz_dual_fisheye.yaml");
  });
  return 0;
}
