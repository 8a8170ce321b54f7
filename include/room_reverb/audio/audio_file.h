#pragma once
// Reading and writing audio files (WAV, FLAC and the other containers libsndfile knows).
#include <string>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

enum class SampleEncoding { kPcm16, kPcm24, kPcm32, kFloat32 };

// Reads every channel of an audio file. Throws InputError with a one-line reason when the
// file is missing, is not audio, holds no samples, has an unsupported sample rate or holds
// non-finite samples.
AudioBuffer readAudioFile(const std::string& path);

// Writes a buffer; the container follows the extension (.wav, .flac; anything else is an
// InputError). FLAC supports PCM 16/24 only; kFloat32 or kPcm32 there is an InputError.
// Samples beyond full scale are clipped by integer encodings, never by kFloat32.
void writeAudioFile(const std::string& path, const AudioBuffer& buffer,
                    SampleEncoding encoding = SampleEncoding::kPcm24);

}  // namespace room_reverb::core
