#include "room_reverb/listening/mushra_page.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/listening/mushra_test_files.h"

namespace room_reverb::core {
namespace {

namespace fs = std::filesystem;

void appendLittleEndian(std::string& out, std::uint32_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((value >> (8 * i)) & 0xFF);
}

// A seed from the stimulus's name, so that its dither does not depend on the order in
// which stimuli are written (FNV-1a, 32 bits).
std::uint32_t nameSeed(const std::string& name) {
  std::uint32_t hash = 2166136261u;
  for (unsigned char c : name) hash = (hash ^ c) * 16777619u;
  return hash;
}

}  // namespace

std::string mushraAudioScriptFile(const std::string& room, const std::string& content, const std::string& condition) {
  return "audio/" + room + "/" + content + "/" + condition + ".js";
}

std::string pcm16WavBytes(const AudioBuffer& audio, std::uint32_t dither_seed) {
  const std::size_t channels = audio.channelCount(), frames = audio.frameCount();
  const std::uint32_t data_bytes = static_cast<std::uint32_t>(channels * frames * 2);
  const std::uint32_t rate = static_cast<std::uint32_t>(std::lround(audio.sample_rate_hz));
  std::string wav;
  wav.reserve(44 + data_bytes);
  wav += "RIFF";
  appendLittleEndian(wav, 36 + data_bytes, 4);
  wav += "WAVEfmt ";
  appendLittleEndian(wav, 16, 4);  // the PCM format chunk's size
  appendLittleEndian(wav, 1, 2);   // PCM
  appendLittleEndian(wav, static_cast<std::uint32_t>(channels), 2);
  appendLittleEndian(wav, rate, 4);
  appendLittleEndian(wav, rate * static_cast<std::uint32_t>(channels) * 2, 4);  // bytes per second
  appendLittleEndian(wav, static_cast<std::uint32_t>(channels) * 2, 2);         // bytes per frame
  appendLittleEndian(wav, 16, 2);
  wav += "data";
  appendLittleEndian(wav, data_bytes, 4);
  // Triangular dither of +-1 LSB (the sum of two uniform draws) makes the rounding error
  // noise independent of the signal, so a decaying tail fades into noise rather than
  // into distortion. std::mt19937 is fixed by the standard: the same bytes everywhere.
  std::mt19937 generator(dither_seed);
  const auto uniform = [&generator] { return generator() / 4294967296.0; };
  for (std::size_t n = 0; n < frames; ++n) {
    for (std::size_t c = 0; c < channels; ++c) {
      const double dither = uniform() - uniform();
      const double value = std::round(audio.channels[c][n] * 32767.0 + dither);
      const auto sample = static_cast<std::int16_t>(std::clamp(value, -32768.0, 32767.0));
      appendLittleEndian(wav, static_cast<std::uint16_t>(sample), 2);
    }
  }
  return wav;
}

std::string base64Encode(const std::string& bytes) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t triple = static_cast<unsigned char>(bytes[i]) << 16 |
                                 static_cast<unsigned char>(bytes[i + 1]) << 8 | static_cast<unsigned char>(bytes[i + 2]);
    for (int shift = 18; shift >= 0; shift -= 6) out += kAlphabet[(triple >> shift) & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    std::uint32_t triple = static_cast<unsigned char>(bytes[i]) << 16;
    if (rest == 2) triple |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += rest == 2 ? kAlphabet[(triple >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string mushraAudioScript(const std::string& key, const AudioBuffer& audio) {
  // The key is a path of safe characters (plan names are letters, digits, '_', '-', '.'),
  // so it needs no escaping inside the quotes.
  return "(window.MUSHRA_AUDIO = window.MUSHRA_AUDIO || {})[\"" + key + "\"] =\n\"" +
         base64Encode(pcm16WavBytes(audio, nameSeed(key))) + "\";\n";
}

std::string mushraTestScript(const std::string& test_json) {
  // JSON is a JavaScript expression, except that engines before ES2019 end a line at
  // U+2028 and U+2029 even inside a string; nlohmann's dump leaves both unescaped, so a
  // question holding one would break the script there.
  std::string safe;
  safe.reserve(test_json.size());
  for (std::size_t i = 0; i < test_json.size(); ++i) {
    if (test_json.compare(i, 3, "\xE2\x80\xA8") == 0 || test_json.compare(i, 3, "\xE2\x80\xA9") == 0) {
      safe += test_json[i + 2] == '\xA8' ? "\\u2028" : "\\u2029";
      i += 2;
    } else {
      safe += test_json[i];
    }
  }
  return "window.MUSHRA_TEST = " + safe + ";\n";
}

void writeMushraPage(const MushraStimuli& stimuli, const std::string& test_json, const std::string& dir) {
  const fs::path root(dir);
  for (const MushraPageAsset& asset : mushraPageAssets()) writeTextFile((root / asset.name).string(), asset.text);
  writeTextFile((root / "test.js").string(), mushraTestScript(test_json));
  for (const MushraStimulus& s : stimuli.stimuli) {
    const fs::path file = root / mushraAudioScriptFile(s.room, s.content, s.condition);
    createFolder(file.parent_path().string());
    writeTextFile(file.string(), mushraAudioScript(mushraStimulusFile(s.room, s.content, s.condition), s.audio));
  }
}

}  // namespace room_reverb::core
