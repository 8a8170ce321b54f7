// The AC3D reader of loadMesh (triangle_mesh.h), which takes a path and picks the
// format by the extension; both up axes, since the y-up one transforms every vertex.
#include "fuzz_common.h"
#include "room_reverb/acoustics/triangle_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string path = room_reverb_fuzz::writeInputFile(data, size, ".ac");
  const auto up = size % 2 == 0 ? room_reverb::core::UpAxis::kZ : room_reverb::core::UpAxis::kY;
  room_reverb_fuzz::expectCleanRejection([&] { room_reverb::core::loadMesh(path, up); });
  return 0;
}
