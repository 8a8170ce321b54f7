// The room model reader (room.yaml, room_model.h), on text in memory.
#include "fuzz_common.h"
#include "room_reverb/acoustics/room_model.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  room_reverb_fuzz::expectCleanRejection(
      [&] { room_reverb::core::parseRoomModel(room_reverb_fuzz::text(data, size)); });
  return 0;
}
