#include "room_reverb/audio/audio_file.h"

#include <sndfile.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"

namespace room_reverb::core {
namespace {

struct SndfileCloser {
  void operator()(SNDFILE* file) const { sf_close(file); }
};
using SndfileHandle = std::unique_ptr<SNDFILE, SndfileCloser>;

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

int sndfileFormat(const std::string& path, SampleEncoding encoding) {
  const std::string ext = lowerExtension(path);
  int subtype = 0;
  switch (encoding) {
    case SampleEncoding::kPcm16: subtype = SF_FORMAT_PCM_16; break;
    case SampleEncoding::kPcm24: subtype = SF_FORMAT_PCM_24; break;
    case SampleEncoding::kPcm32: subtype = SF_FORMAT_PCM_32; break;
    case SampleEncoding::kFloat32: subtype = SF_FORMAT_FLOAT; break;
  }
  if (ext == "wav") return SF_FORMAT_WAV | subtype;
  if (ext == "flac") {
    if (encoding == SampleEncoding::kFloat32 || encoding == SampleEncoding::kPcm32) {
      throw InputError(path + ": FLAC stores 16- or 24-bit integer samples only");
    }
    return SF_FORMAT_FLAC | subtype;
  }
  throw InputError(path + ": unknown audio extension '." + ext + "' (use .wav or .flac)");
}

}  // namespace

AudioBuffer readAudioFile(const std::string& path) {
  requireExistingFile(path, "audio file");

  SF_INFO info{};
  SndfileHandle file(sf_open(path.c_str(), SFM_READ, &info));
  if (!file) {
    throw InputError(path + ": not a readable audio file (" + sf_strerror(nullptr) + ")");
  }
  if (info.channels <= 0) throw InputError(path + ": has no audio channels");
  if (info.frames <= 0) throw InputError(path + ": holds no samples");

  std::vector<float> interleaved(static_cast<std::size_t>(info.frames) * info.channels);
  const sf_count_t read = sf_readf_float(file.get(), interleaved.data(), info.frames);
  if (read <= 0) throw InputError(path + ": could not read samples (" + sf_strerror(file.get()) + ")");
  interleaved.resize(static_cast<std::size_t>(read) * info.channels);

  AudioBuffer buffer = deinterleave(interleaved, static_cast<std::size_t>(info.channels),
                                    static_cast<double>(info.samplerate));
  validateAudioBuffer(buffer, path);
  return buffer;
}

void writeAudioFile(const std::string& path, const AudioBuffer& buffer, SampleEncoding encoding) {
  validateAudioBuffer(buffer, path);
  SF_INFO info{};
  info.channels = static_cast<int>(buffer.channelCount());
  info.samplerate = static_cast<int>(std::lround(buffer.sample_rate_hz));
  info.format = sndfileFormat(path, encoding);
  if (!sf_format_check(&info)) {
    std::ostringstream os;
    os << path << ": libsndfile cannot write " << info.channels << " channels at "
       << info.samplerate << " Hz in this format";
    throw InputError(os.str());
  }
  SndfileHandle file(sf_open(path.c_str(), SFM_WRITE, &info));
  if (!file) throw InputError(path + ": cannot open for writing (" + sf_strerror(nullptr) + ")");
  // Integer encodings clip rather than wrap around at full scale.
  sf_command(file.get(), SFC_SET_CLIPPING, nullptr, SF_TRUE);
  const std::vector<float> interleaved = interleave(buffer);
  const auto frames = static_cast<sf_count_t>(buffer.frameCount());
  if (sf_writef_float(file.get(), interleaved.data(), frames) != frames) {
    throw InputError(path + ": write failed (" + std::string(sf_strerror(file.get())) + ")");
  }
}

}  // namespace room_reverb::core
