// The audio reader (audio_file.h): libsndfile picks the container from the bytes, so a
// .wav name covers WAV, FLAC and the other formats it recognises by their header.
#include "fuzz_common.h"
#include "room_reverb/audio/audio_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string path = room_reverb_fuzz::writeInputFile(data, size, ".wav");
  room_reverb_fuzz::expectCleanRejection([&] { room_reverb::core::readAudioFile(path); });
  return 0;
}
