// The simulation job and result decoders (simulation_wire.h), on bytes in memory: what a
// room_simulator node's simulate_job service and a simulate-worker take from the network
// or a pipe. A job is split and its scene decoded (the BVH built), but not simulated.
#include "fuzz_common.h"
#include "room_reverb/acoustics/simulation_wire.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace room_reverb::core;
  room_reverb_fuzz::expectCleanRejection([&] {
    const JobParts parts = splitJob(data, size);
    decodeScene(parts.scene, parts.scene_size);
  });
  room_reverb_fuzz::expectCleanRejection([&] { decodeResult(data, size); });
  return 0;
}
