// The MUSHRA plan reader (mushra_plan.h), on text in memory; relative paths resolve
// against the repository, so a plan naming the project's own data files gets past the
// file checks into the checks of the test's design.
#include "fuzz_common.h"
#include "room_reverb/listening/mushra_plan.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  room_reverb_fuzz::expectCleanRejection([&] {
    room_reverb::core::parseMushraPlan(room_reverb_fuzz::text(data, size), ROOM_REVERB_SOURCE_DIR, "fuzz_plan.yaml");
  });
  return 0;
}
