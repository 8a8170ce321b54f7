// Virtual-loudspeaker binaural decoder: a mode-matching decoder onto a loudspeaker layout,
// each loudspeaker rendered through the HRIR of its direction.
//
// Mode matching (Zotter & Frank, "Ambisonics", 2019, sec. 4.9.3): the loudspeaker gains g
// of an ambisonic signal b solve Y_L^T g = b in the least-norm sense, g = pinv(Y_L^T) b,
// so the layout re-encodes to exactly b wherever its harmonic matrix has full rank. On a
// t-design this equals the sampling decoder; unlike sampling it needs no quadrature
// weights on other layouts. Where the layout cannot represent a harmonic combination (the
// paper's three rings at order 3) the pseudo-inverse drops it instead of amplifying it.
// max-rE weights (Daniel 2001) then taper the orders above the frequency where order N
// stops describing the field around the head (decoder_support::maxReTaper). AllRAD is not
// used: with virtual loudspeakers there is no real layout whose gaps need a VBAP detour.
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "decoder_support.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

// Singular values below this fraction of the largest are treated as zero: a harmonic
// combination the layout cannot produce is left out rather than boosted.
constexpr double kRankTolerance = 1e-6;

// (loudspeakers x channels) decoding matrix: pinv(E) = V diag(1/s) U^T for the
// (channels x loudspeakers) encoder E = U diag(s) V^T, over the kept singular values.
Eigen::MatrixXd modeMatchingDecoder(int order, const std::vector<Eigen::Vector3d>& layout) {
  const Eigen::MatrixXd encoder = decoder_support::harmonicMatrix(order, layout).transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(encoder, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& singular = svd.singularValues();  // descending
  const Eigen::VectorXd inverse =
      singular.unaryExpr([&](double s) { return s > kRankTolerance * singular(0) ? 1.0 / s : 0.0; });
  return svd.matrixV() * inverse.asDiagonal() * svd.matrixU().transpose();
}

// The filters with decoder_support::maxReTaper applied, through the frequency domain (on
// twice their length, so the smooth zero-phase taper's short ringing does not wrap).
std::vector<Hrir> withMaxReAboveOrderLimit(const std::vector<Hrir>& filters, int order, double sample_rate_hz) {
  const std::size_t length = filters.front().left.size();
  const std::size_t fft_size = nextFastFftSize(2 * length);
  std::vector<Eigen::MatrixXcd> spectra = decoder_support::filterSpectra(filters, fft_size);
  for (std::size_t k = 0; k < spectra.size(); ++k) {
    const double frequency_hz = sample_rate_hz * static_cast<double>(k) / static_cast<double>(fft_size);
    spectra[k] = decoder_support::maxReTaper(order, frequency_hz).asDiagonal() * spectra[k];
  }
  return decoder_support::filtersFromSpectra(spectra, fft_size, length);
}

}  // namespace

BinauralDecoder makeVirtualLoudspeakerDecoder(const HrtfSet& hrtf, int order,
                                              const std::vector<Eigen::Vector3d>& layout,
                                              const VirtualLoudspeakerOptions& options) {
  decoder_support::checkDecoderOrder(order);
  const int channels = ambisonicChannelCount(order);
  if (layout.empty()) throw InputError("the virtual loudspeaker layout is empty");
  if (layout.size() < static_cast<std::size_t>(channels)) {
    throw InputError("an order-" + std::to_string(order) + " virtual loudspeaker decoder needs at least " +
                     std::to_string(channels) + " loudspeakers; the layout has " + std::to_string(layout.size()));
  }
  const std::size_t filter_length = decoder_support::filterLength(hrtf, options.filter_length);
  const Eigen::MatrixXd gains = modeMatchingDecoder(order, layout);

  BinauralDecoder decoder;
  decoder.order = order;
  decoder.sample_rate_hz = hrtf.sampleRateHz();
  decoder.filters.assign(static_cast<std::size_t>(channels),
                         Hrir{std::vector<float>(filter_length, 0.0f), std::vector<float>(filter_length, 0.0f)});
  for (std::size_t s = 0; s < layout.size(); ++s) {
    const Hrir hrir = options.interpolate_hrirs ? hrtf.interpolated(layout[s]) : hrtf.hrir(hrtf.nearest(layout[s]));
    const std::size_t taps = std::min(filter_length, hrir.left.size());
    for (int c = 0; c < channels; ++c) {
      const auto gain = static_cast<float>(gains(static_cast<Eigen::Index>(s), c));
      Hrir& filter = decoder.filters[static_cast<std::size_t>(c)];
      for (std::size_t n = 0; n < taps; ++n) {
        filter.left[n] += gain * hrir.left[n];
        filter.right[n] += gain * hrir.right[n];
      }
    }
  }
  std::ostringstream method;
  method << "virtual loudspeakers order " << order << ", mode matching onto " << layout.size() << " loudspeakers";
  if (options.max_re_weights) {
    decoder.filters = withMaxReAboveOrderLimit(decoder.filters, order, decoder.sample_rate_hz);
    method << ", max-rE weights above " << std::lround(decoder_support::orderLimitFrequencyHz(order)) << " Hz";
  }
  method << (options.interpolate_hrirs ? ", interpolated HRIRs" : ", nearest HRIRs") << ", " << filter_length
         << " taps";
  if (!hrtf.description().empty()) method << " (" << hrtf.description() << ")";
  decoder.method = method.str();
  return decoder;
}

}  // namespace room_reverb::core
