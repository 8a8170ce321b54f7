#include "room_reverb/ambisonics/bformat.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr float kFumaWGain = 0.70710678f;  // FuMa W = SN3D W / sqrt(2)

void requireFourChannels(const AudioBuffer& buffer, const char* what) {
  if (buffer.channelCount() != 4) {
    std::ostringstream os;
    os << what << ": first-order B-format needs 4 channels, got " << buffer.channelCount();
    throw InputError(os.str());
  }
}

void scale(std::vector<float>& channel, float gain) {
  for (float& sample : channel) sample *= gain;
}

}  // namespace

AmbisonicFormat parseAmbisonicFormat(const std::string& name) {
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (lower == "ambix") return AmbisonicFormat::kAmbiX;
  if (lower == "fuma") return AmbisonicFormat::kFuMa;
  throw InputError("unknown ambisonic format '" + name + "' (use ambix or fuma)");
}

std::string toString(AmbisonicFormat format) {
  return format == AmbisonicFormat::kAmbiX ? "ambix" : "fuma";
}

AudioBuffer fumaToAmbix(const AudioBuffer& fuma) {
  requireFourChannels(fuma, "FuMa input");
  AudioBuffer ambix = fuma;
  // FuMa order W X Y Z -> ACN order W Y Z X.
  ambix.channels[kAcnW] = fuma.channels[0];
  scale(ambix.channels[kAcnW], 1.0f / kFumaWGain);
  ambix.channels[kAcnY] = fuma.channels[2];
  ambix.channels[kAcnZ] = fuma.channels[3];
  ambix.channels[kAcnX] = fuma.channels[1];
  return ambix;
}

AudioBuffer ambixToFuma(const AudioBuffer& ambix) {
  requireFourChannels(ambix, "AmbiX input");
  AudioBuffer fuma = ambix;
  fuma.channels[0] = ambix.channels[kAcnW];
  scale(fuma.channels[0], kFumaWGain);
  fuma.channels[1] = ambix.channels[kAcnX];
  fuma.channels[2] = ambix.channels[kAcnY];
  fuma.channels[3] = ambix.channels[kAcnZ];
  return fuma;
}

int ambixOrder(const AudioBuffer& ambix, const std::string& what) {
  for (int n = 0; n <= kMaxAmbisonicOrder; ++n) {
    if (ambix.channelCount() == static_cast<std::size_t>(ambisonicChannelCount(n))) return n;
  }
  throw InputError(what + " has " + std::to_string(ambix.channelCount()) +
                   " channels; AmbiX of order 0-3 has 1, 4, 9 or 16");
}

AudioBuffer toAmbix(const AudioBuffer& buffer, AmbisonicFormat from) {
  if (from == AmbisonicFormat::kFuMa) return fumaToAmbix(buffer);
  requireFourChannels(buffer, "AmbiX input");
  return buffer;
}

double diffuseDirectionalToOmniRatio(const AudioBuffer& buffer, double skip_s) {
  requireFourChannels(buffer, "B-format input");
  const auto start = static_cast<std::size_t>(std::max(0.0, skip_s) * buffer.sample_rate_hz);
  double omni = 0.0;
  double directional = 0.0;
  for (std::size_t c = 0; c < 4; ++c) {
    double energy = 0.0;
    const auto& channel = buffer.channels[c];
    for (std::size_t n = std::min(start, channel.size()); n < channel.size(); ++n) {
      energy += static_cast<double>(channel[n]) * channel[n];
    }
    (c == 0 ? omni : directional) += energy;
  }
  if (omni <= 0.0) return 0.0;
  return directional / omni;
}

std::string checkAmbisonicFormat(const AudioBuffer& buffer, AmbisonicFormat stated) {
  const double ratio = diffuseDirectionalToOmniRatio(buffer);
  if (ratio <= 0.0) return "";
  const double expected = stated == AmbisonicFormat::kFuMa ? 2.0 : 1.0;
  const double other = stated == AmbisonicFormat::kFuMa ? 1.0 : 2.0;
  const double off_expected = std::abs(std::log(ratio / expected));
  const double off_other = std::abs(std::log(ratio / other));
  if (off_other < off_expected && off_expected > std::log(1.4)) {
    std::ostringstream os;
    os.precision(2);
    os << "the directional-to-omni energy ratio of the late part is " << std::fixed << ratio
       << ", closer to " << (stated == AmbisonicFormat::kFuMa ? "AmbiX/SN3D (1.0)" : "FuMa (2.0)")
       << " than to the stated " << toString(stated) << " (" << expected
       << "); check the file's convention";
    return os.str();
  }
  return "";
}

}  // namespace room_reverb::core
