#pragma once
// The browser page of a MUSHRA test (`room_reverb mushra make` writes it beside test.json;
// `room_reverb mushra serve` serves it):
//
//   DIR/index.html, mushra.js, mushra.css          the page (web/mushra, compiled in)
//   DIR/test.js                                    window.MUSHRA_TEST = <test.json>;
//   DIR/audio/<room>/<content>/<condition>.js      one stimulus as a base64 WAV
//
// The page must work opened from the file system, where a browser lets it load scripts
// but not fetch() the files next to it; so the test and the audio come as scripts. The
// audio is 16-bit PCM WAV with triangular dither: half the size of float32 (base64 adds a
// third), with the quantisation noise near -98 dBFS, far below what a listener hears at
// the test's -23 LUFS, and read by every browser's decodeAudioData. The float32 WAVs in
// stimuli/ stay the canonical stimuli. web/mushra/mushra.js describes the page itself.
#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/listening/mushra_stimuli.h"

namespace room_reverb::core {

// One file of the page, as compiled into the library from web/mushra
// (cmake/embed_web_assets.cmake generates mushraPageAssets()).
struct MushraPageAsset {
  const char* name;  // "index.html"
  const char* text;
};
const std::vector<MushraPageAsset>& mushraPageAssets();

// Where a stimulus's audio script goes, relative to DIR.
std::string mushraAudioScriptFile(const std::string& room, const std::string& content, const std::string& condition);

// `audio` as the bytes of a 16-bit PCM WAV file (RIFF/WAVE, little-endian), with TPDF
// dither from a generator seeded by `dither_seed`, so that the same stimulus always gives
// the same bytes. Samples beyond full scale are clipped.
std::string pcm16WavBytes(const AudioBuffer& audio, std::uint32_t dither_seed);

// RFC 4648 base64 (with '=' padding).
std::string base64Encode(const std::string& bytes);

// The script that hands one stimulus to the page: it stores the base64 WAV in
// window.MUSHRA_AUDIO under `key` (the stimulus's file in test.json).
std::string mushraAudioScript(const std::string& key, const AudioBuffer& audio);

// The script form of test.json.
std::string mushraTestScript(const std::string& test_json);

// Writes the page, test.js and every stimulus's audio script into `dir` (which exists).
// InputError naming the file that cannot be written.
void writeMushraPage(const MushraStimuli& stimuli, const std::string& test_json, const std::string& dir);

}  // namespace room_reverb::core
