// SOFA through the HRTF loader (hrtf_set.h: libmysofa, then the convention checks and the
// resampling), which takes a path.
#include "fuzz_common.h"
#include "room_reverb/binaural/hrtf_set.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string path = room_reverb_fuzz::writeInputFile(data, size, ".sofa");
  room_reverb_fuzz::expectCleanRejection([&] { room_reverb::core::HrtfSet::loadSofa(path); });
  return 0;
}
