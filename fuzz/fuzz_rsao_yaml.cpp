// The RSAO YAML reader (rsao_yaml.h), on text in memory.
#include "fuzz_common.h"
#include "room_reverb/rsao/rsao_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  room_reverb_fuzz::expectCleanRejection(
      [&] { room_reverb::core::parseRsaoYaml(room_reverb_fuzz::text(data, size), "fuzz.yaml"); });
  return 0;
}
