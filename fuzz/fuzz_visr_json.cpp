// The VISR JSON import (rsao_visr_json.h), on text in memory, for the first object and
// for an object id (a different lookup path).
#include "fuzz_common.h"
#include "room_reverb/rsao/rsao_visr_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string json = room_reverb_fuzz::text(data, size);
  room_reverb_fuzz::expectCleanRejection([&] { room_reverb::core::visrJsonToRsao(json); });
  room_reverb_fuzz::expectCleanRejection([&] { room_reverb::core::visrJsonToRsao(json, 0); });
  return 0;
}
