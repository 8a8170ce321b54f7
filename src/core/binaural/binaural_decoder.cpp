#include "room_reverb/binaural/binaural_decoder.h"

#include <algorithm>
#include <complex>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/binaural/loudspeaker_layout.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

void checkFilterCount(const BinauralDecoder& decoder) {
  if (decoder.order < 1 || decoder.order > kMaxAmbisonicOrder ||
      decoder.filters.size() != static_cast<std::size_t>(ambisonicChannelCount(decoder.order)) ||
      decoder.filters.front().left.empty()) {
    throw InputError("the binaural decoder is incomplete: make it with makeBinauralDecoder()");
  }
}

}  // namespace

DecoderMethod parseDecoderMethod(const std::string& name) {
  if (name == "virtual_loudspeakers") return DecoderMethod::kVirtualLoudspeakers;
  if (name == "least_squares") return DecoderMethod::kLeastSquares;
  if (name == "magls") return DecoderMethod::kMagLs;
  throw InputError("unknown binaural decoder '" + name + "' (use magls, least_squares or virtual_loudspeakers)");
}

std::string toString(DecoderMethod method) {
  switch (method) {
    case DecoderMethod::kVirtualLoudspeakers: return "virtual_loudspeakers";
    case DecoderMethod::kLeastSquares: return "least_squares";
    case DecoderMethod::kMagLs: return "magls";
  }
  return "magls";
}

BinauralDecoder makeBinauralDecoder(const HrtfSet& hrtf, int order, DecoderMethod method) {
  switch (method) {
    case DecoderMethod::kVirtualLoudspeakers:
      return makeVirtualLoudspeakerDecoder(hrtf, order, loudspeakerLayoutByName(kDefaultLoudspeakerLayout));
    case DecoderMethod::kLeastSquares: return makeLeastSquaresDecoder(hrtf, order);
    case DecoderMethod::kMagLs: break;
  }
  return makeMagLsDecoder(hrtf, order);
}

AudioBuffer decodeToBinaural(const AudioBuffer& ambix, const BinauralDecoder& decoder) {
  checkFilterCount(decoder);
  validateAudioBuffer(ambix, "the ambisonic signal");
  const auto channels = static_cast<std::size_t>(ambisonicChannelCount(decoder.order));
  if (ambix.channelCount() != channels) {
    throw InputError("an order-" + std::to_string(decoder.order) + " binaural decoder takes " +
                     std::to_string(channels) + " AmbiX channels; the signal has " +
                     std::to_string(ambix.channelCount()));
  }
  if (ambix.sample_rate_hz != decoder.sample_rate_hz) {
    throw InputError("the ambisonic signal is at " + std::to_string(ambix.sample_rate_hz) +
                     " Hz but the decoder at " + std::to_string(decoder.sample_rate_hz) + " Hz; resample it first");
  }
  // Summing the channels' products in the frequency domain costs one inverse FFT per ear
  // instead of one per channel and ear.
  const std::size_t filter_length = decoder.filters.front().left.size();
  const std::size_t out_length = ambix.frameCount() + filter_length - 1;
  RealFft fft(nextFastFftSize(out_length));
  std::vector<float> padded(fft.size());
  const auto spectrumOf = [&](const std::vector<float>& x) {
    std::fill(padded.begin(), padded.end(), 0.0f);
    std::copy(x.begin(), x.end(), padded.begin());
    return fft.forward(padded);
  };
  std::vector<std::complex<float>> left(fft.spectrumSize()), right(fft.spectrumSize());
  for (std::size_t c = 0; c < channels; ++c) {
    const auto signal = spectrumOf(ambix.channels[c]);
    const auto filter_left = spectrumOf(decoder.filters[c].left);
    const auto filter_right = spectrumOf(decoder.filters[c].right);
    for (std::size_t k = 0; k < signal.size(); ++k) {
      left[k] += signal[k] * filter_left[k];
      right[k] += signal[k] * filter_right[k];
    }
  }
  AudioBuffer binaural;
  binaural.sample_rate_hz = decoder.sample_rate_hz;
  for (const auto* spectrum : {&left, &right}) {
    std::vector<float> ear = fft.inverse(*spectrum);
    ear.resize(out_length);
    binaural.channels.push_back(std::move(ear));
  }
  return binaural;
}

Hrir decodedPlaneWaveResponse(const BinauralDecoder& decoder, const Eigen::Vector3d& direction) {
  checkFilterCount(decoder);
  const std::vector<double> harmonics = sn3dHarmonics(decoder.order, direction);
  const std::size_t length = decoder.filters.front().left.size();
  Hrir response{std::vector<float>(length, 0.0f), std::vector<float>(length, 0.0f)};
  for (std::size_t c = 0; c < harmonics.size(); ++c) {
    const auto gain = static_cast<float>(harmonics[c]);
    for (std::size_t n = 0; n < length; ++n) {
      response.left[n] += gain * decoder.filters[c].left[n];
      response.right[n] += gain * decoder.filters[c].right[n];
    }
  }
  return response;
}

}  // namespace room_reverb::core
