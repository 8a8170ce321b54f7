// The measurements.yaml reader (measurements.h), on text in memory; relative paths
// resolve against /tmp, where the named files do not exist.
#include "fuzz_common.h"
#include "room_reverb/evaluation/measurements.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  room_reverb_fuzz::expectCleanRejection(
      [&] { room_reverb::core::parseMeasurements(room_reverb_fuzz::text(data, size), "/tmp"); });
  return 0;
}
