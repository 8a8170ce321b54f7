#include "decoder_support.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/ambisonics/max_re_weights.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core::decoder_support {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHeadRadiusM = 0.0875;
constexpr double kSpeedOfSoundMS = 343.0;

std::vector<float> truncatedWithFadeOut(std::vector<float> impulse_response, std::size_t length) {
  impulse_response.resize(length);
  const std::size_t fade = std::max<std::size_t>(1, length / 8);
  for (std::size_t i = 0; i < fade; ++i) {
    const double gain = 0.5 * (1.0 + std::cos(kPi * (i + 1.0) / static_cast<double>(fade)));
    impulse_response[length - fade + i] *= static_cast<float>(gain);
  }
  return impulse_response;
}

}  // namespace

void checkDecoderOrder(int order) {
  if (order < 1 || order > kMaxAmbisonicOrder) {
    throw InputError("binaural decoder order " + std::to_string(order) + " is not supported (use 1, 2 or 3)");
  }
}

std::size_t filterLength(const HrtfSet& hrtf, std::size_t requested) {
  if (requested == 0) return hrtf.length() + kDecoderFilterMargin;
  if (requested < hrtf.length()) {
    throw InputError("decoder filter length " + std::to_string(requested) + " is shorter than the HRIRs (" +
                     std::to_string(hrtf.length()) + " taps)");
  }
  return requested;
}

double orderLimitFrequencyHz(int order) { return order * kSpeedOfSoundMS / (2.0 * kPi * kHeadRadiusM); }

Eigen::VectorXd maxReTaper(int order, double frequency_hz) {
  const std::vector<double> weights = maxReChannelWeights(order);
  const Eigen::Map<const Eigen::VectorXd> max_re(weights.data(), static_cast<Eigen::Index>(weights.size()));
  const double octaves = frequency_hz > 0.0 ? std::log2(frequency_hz / orderLimitFrequencyHz(order)) : -1.0;
  const double blend = octaves <= -0.5 ? 0.0 : octaves >= 0.5 ? 1.0 : 0.5 * (1.0 + std::sin(kPi * octaves));
  return Eigen::VectorXd::Ones(max_re.size()) + blend * (max_re - Eigen::VectorXd::Ones(max_re.size()));
}

Eigen::VectorXd sn3dDiffuseChannelPowers(int order) {
  Eigen::VectorXd powers(ambisonicChannelCount(order));
  for (int l = 0; l <= order; ++l) powers.segment(l * l, 2 * l + 1).setConstant(1.0 / (2.0 * l + 1.0));
  return powers;
}

Eigen::MatrixXd harmonicMatrix(int order, const std::vector<Eigen::Vector3d>& directions) {
  Eigen::MatrixXd y(static_cast<Eigen::Index>(directions.size()), ambisonicChannelCount(order));
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const std::vector<double> harmonics = sn3dHarmonics(order, directions[i]);
    y.row(static_cast<Eigen::Index>(i)) = Eigen::Map<const Eigen::RowVectorXd>(harmonics.data(), y.cols());
  }
  return y;
}

std::vector<Eigen::MatrixXcd> pairSpectra(std::size_t count, const std::function<const Hrir&(std::size_t)>& pair,
                                          std::size_t fft_size) {
  RealFft fft(fft_size);
  std::vector<Eigen::MatrixXcd> spectra(fft.spectrumSize(), Eigen::MatrixXcd(static_cast<Eigen::Index>(count), 2));
  std::vector<float> padded(fft_size);
  std::vector<std::complex<float>> bins(fft.spectrumSize());
  for (std::size_t d = 0; d < count; ++d) {
    const Hrir& responses = pair(d);
    for (int ear = 0; ear < 2; ++ear) {
      const std::vector<float>& samples = ear == 0 ? responses.left : responses.right;
      std::fill(padded.begin(), padded.end(), 0.0f);
      std::copy(samples.begin(), samples.end(), padded.begin());
      fft.forward(padded.data(), bins.data());
      for (std::size_t k = 0; k < bins.size(); ++k) spectra[k](static_cast<Eigen::Index>(d), ear) = bins[k];
    }
  }
  return spectra;
}

std::vector<Eigen::MatrixXcd> hrtfSpectra(const HrtfSet& hrtf, std::size_t fft_size) {
  return pairSpectra(hrtf.size(), [&](std::size_t i) -> const Hrir& { return hrtf.hrir(i); }, fft_size);
}

std::vector<Eigen::MatrixXcd> filterSpectra(const std::vector<Hrir>& filters, std::size_t fft_size) {
  return pairSpectra(filters.size(), [&](std::size_t i) -> const Hrir& { return filters[i]; }, fft_size);
}

std::vector<Hrir> filtersFromSpectra(const std::vector<Eigen::MatrixXcd>& spectra, std::size_t fft_size,
                                     std::size_t filter_length) {
  RealFft fft(fft_size);
  const Eigen::Index channels = spectra.front().rows();
  std::vector<Hrir> filters(static_cast<std::size_t>(channels));
  std::vector<std::complex<float>> bins(fft.spectrumSize());
  for (Eigen::Index c = 0; c < channels; ++c) {
    for (int ear = 0; ear < 2; ++ear) {
      for (std::size_t k = 0; k < bins.size(); ++k) bins[k] = std::complex<float>(spectra[k](c, ear));
      std::vector<float> impulse_response = truncatedWithFadeOut(fft.inverse(bins), filter_length);
      (ear == 0 ? filters[static_cast<std::size_t>(c)].left : filters[static_cast<std::size_t>(c)].right) =
          std::move(impulse_response);
    }
  }
  return filters;
}

}  // namespace room_reverb::core::decoder_support
