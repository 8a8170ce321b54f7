// The MUSHRA results CSV reader (mushra_results.h), on text in memory, on both scales.
#include "fuzz_common.h"
#include "room_reverb/listening/mushra_results.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string csv = room_reverb_fuzz::text(data, size);
  for (const auto scale : {room_reverb::core::MushraScale::kZeroToFive, room_reverb::core::MushraScale::kZeroToHundred}) {
    room_reverb_fuzz::expectCleanRejection(
        [&] { room_reverb::core::parseMushraResultsCsv(csv, "fuzz.csv", scale); });
  }
  return 0;
}
