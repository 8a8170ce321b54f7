#include "room_reverb/binaural/offline_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/audio/channel_mix.h"
#include "room_reverb/audio/convolution.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

AudioBuffer loadDrySource(const std::string& path, std::vector<std::string>& notes) {
  const AudioBuffer file = readAudioFile(path);
  if (file.channelCount() > 1) {
    notes.push_back("the " + std::to_string(file.channelCount()) + "-channel source " + path + " is mixed to mono");
  }
  if (file.sample_rate_hz != kInternalSampleRateHz) {
    std::ostringstream os;
    os << "the source " << path << " was resampled from " << file.sample_rate_hz << " Hz to 48000 Hz";
    notes.push_back(os.str());
  }
  return toInternalRate(mixToMono(file));
}

AudioBuffer ambixRoomResponse(const AudioBuffer& response, const std::string& layout, std::vector<std::string>& notes) {
  validateAudioBuffer(response, "the room response");
  AudioBuffer ambix;
  if (layout == "fuma") {
    if (response.channelCount() != 4) {
      throw InputError("a first-order FuMa B-format response has 4 channels, this one has " +
                       std::to_string(response.channelCount()));
    }
    ambix = toAmbix(response, AmbisonicFormat::kFuMa);
  } else if (layout == "ambix") {
    ambixOrder(response);
    ambix = response;
  } else if (layout == "mono") {
    if (response.channelCount() != 1) {
      throw InputError("a mono room response has 1 channel, this one has " + std::to_string(response.channelCount()));
    }
    ambix = response;
  } else {
    throw InputError("the room response's layout \"" + layout + "\" is not one of fuma, ambix, mono");
  }
  if (ambix.sample_rate_hz != kInternalSampleRateHz) {
    std::ostringstream os;
    os << "the room response was resampled from " << ambix.sample_rate_hz << " Hz to 48000 Hz";
    notes.push_back(os.str());
    ambix = toInternalRate(ambix);
  }
  return ambix;
}

AudioBuffer binauralRoomResponse(const AudioBuffer& ambix, const BinauralDecoder& decoder,
                                 const Eigen::Quaterniond& head_in_room) {
  validateAudioBuffer(ambix, "the room response");
  const int order = ambixOrder(ambix);
  if (order > decoder.order) {
    throw InputError("an order-" + std::to_string(order) + " room response cannot go through an order-" +
                     std::to_string(decoder.order) + " decoder");
  }
  if (ambix.sample_rate_hz != decoder.sample_rate_hz) {
    std::ostringstream os;
    os << "the room response is at " << ambix.sample_rate_hz << " Hz, the decoder at " << decoder.sample_rate_hz << " Hz";
    throw InputError(os.str());
  }
  AudioBuffer field = ambix;
  field.channels.resize(static_cast<std::size_t>(ambisonicChannelCount(decoder.order)),
                        std::vector<float>(ambix.frameCount(), 0.0f));
  rotateAmbisonicBuffer(field, headTrackingRotation(head_in_room, decoder.order));
  return decodeToBinaural(field, decoder);
}

int binauralDecoderOrder(const AudioBuffer& ambix) { return std::max(ambixOrder(ambix), 1); }

BinauralRender convolveBinaural(const AudioBuffer& mono_source, const AudioBuffer& brir) {
  validateAudioBuffer(mono_source, "the source");
  validateAudioBuffer(brir, "the binaural room response");
  if (mono_source.channelCount() != 1) throw InputError("convolveBinaural: the source must be mono");
  if (brir.channelCount() != 2) throw InputError("convolveBinaural: the binaural response must have 2 channels");
  if (mono_source.sample_rate_hz != brir.sample_rate_hz) {
    throw InputError("convolveBinaural: the source and the response have different sample rates");
  }
  BinauralRender render;
  render.audio = makeSilentBuffer(2, 0, brir.sample_rate_hz);
  float peak = 0.0f;
  bool finite = true;
  for (std::size_t ear = 0; ear < 2; ++ear) {
    render.audio.channels[ear] = fftConvolve(mono_source.channels[0], brir.channels[ear]);
    for (float v : render.audio.channels[ear]) {
      finite = finite && std::isfinite(v);
      peak = std::max(peak, std::abs(v));
    }
  }
  // Finite inputs far beyond full scale (a corrupt float file holds values up to 3e38)
  // overflow the convolution; say which input is out of range rather than write noise.
  if (!finite) {
    const auto largest = [](const std::vector<float>& x) {
      float m = 0.0f;
      for (float v : x) m = std::max(m, std::abs(v));
      return m;
    };
    char text[240];
    std::snprintf(text, sizeof text,
                  "the render overflows 32-bit float: the source peaks at %.3g and the binaural response at %.3g "
                  "(full scale is 1); is one of the files corrupt?",
                  static_cast<double>(largest(mono_source.channels[0])),
                  static_cast<double>(std::max(largest(brir.channels[0]), largest(brir.channels[1]))));
    throw InputError(text);
  }
  if (peak > 1.0f) {
    const float gain = 0.891f / peak;  // -1 dBFS
    for (auto& ear : render.audio.channels) {
      for (float& v : ear) v *= gain;
    }
    render.gain_db = 20.0 * std::log10(gain);
    peak *= gain;
  }
  render.peak_dbfs = 20.0 * std::log10(std::max(peak, 1e-30f));
  return render;
}

}  // namespace room_reverb::core
