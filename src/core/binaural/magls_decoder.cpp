// SH-domain binaural decoders: least-squares and magnitude-least-squares fits of the HRTF
// set onto the order-N harmonics (binaural_decoder.h says why and cites the methods).
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>

#include "decoder_support.h"
#include "diffuse_field_covariance.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/common/error.h"
#include "sphere_quadrature.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Per FFT bin, a (directions or channels) x 2 ears matrix.
using Spectra = std::vector<Eigen::MatrixXcd>;

// Magnitudes of `target` with the phases of `reference`, element by element.
Eigen::MatrixXcd withPhaseOf(const Eigen::MatrixXcd& target, const Eigen::MatrixXcd& reference) {
  return target.cwiseAbs().cwiseProduct(reference.unaryExpr([](const std::complex<double>& z) {
    return std::polar(1.0, std::arg(z));
  }));
}

// The set's bulk delay in whole samples: the median over directions of the mean of the
// two ears' onsets, about when the sound passes the head centre. The fit works on HRTFs
// with this delay taken out, as the eMagLS code of Deppisch, Helmholz & Ahrens (I3DA
// 2021) does: what is left of the phase is the interaural part, of low spherical order,
// and the phase that MagLS carries up from the cutoff stays near the head centre's
// instead of near t = 0, where half of the filters' high-frequency energy would wrap
// round to negative times and be cut. Putting the same delay back keeps the decoder in time with direct HRTF rendering.
std::size_t bulkDelaySamples(const HrtfSet& hrtf) {
  std::vector<double> centres(hrtf.size());
  for (std::size_t i = 0; i < hrtf.size(); ++i) centres[i] = 0.5 * (hrtf.onset(i).left + hrtf.onset(i).right);
  std::nth_element(centres.begin(), centres.begin() + static_cast<std::ptrdiff_t>(centres.size() / 2), centres.end());
  return static_cast<std::size_t>(std::max(0.0, std::round(centres[centres.size() / 2])));
}

// exp(-i omega delay) at bin k of an fft_size transform.
std::complex<double> delayPhasor(std::size_t k, std::size_t fft_size, double delay_samples) {
  return std::polar(1.0, -2.0 * kPi * static_cast<double>(k) * delay_samples / static_cast<double>(fft_size));
}

std::string describe(const char* name, int order, double cutoff_hz, const ShDecoderOptions& options,
                     std::size_t filter_length, const HrtfSet& hrtf) {
  std::ostringstream text;
  text << name << " order " << order;
  if (std::isfinite(cutoff_hz)) text << ", magnitude fit above " << std::lround(cutoff_hz) << " Hz";
  if (options.max_re_weights) {
    text << ", max-rE weights above " << std::lround(decoder_support::orderLimitFrequencyHz(order)) << " Hz";
  }
  if (options.diffuse_field_covariance) text << ", diffuse-field covariance constraint";
  text << ", " << filter_length << " taps, " << hrtf.size() << " HRTF directions";
  if (!hrtf.description().empty()) text << " (" << hrtf.description() << ")";
  return text.str();
}

// Fits complex HRTFs below `cutoff_hz` and magnitudes with the previous bin's phase from
// there up (cutoff_hz = infinity: plain least squares everywhere).
BinauralDecoder fitShDecoder(const HrtfSet& hrtf, int order, double cutoff_hz, const ShDecoderOptions& options,
                             const char* name) {
  decoder_support::checkDecoderOrder(order);
  const int channels = ambisonicChannelCount(order);
  if (hrtf.size() < static_cast<std::size_t>(channels)) {
    throw InputError("an order-" + std::to_string(order) + " fit needs at least " + std::to_string(channels) +
                     " HRTF directions; the set has " + std::to_string(hrtf.size()));
  }
  const std::size_t filter_length = decoder_support::filterLength(hrtf, options.filter_length);
  // Twice the filter length: the frequency grid is fine enough for the phase to be
  // carried from bin to bin, and what the fit spreads in time has room before truncation.
  const std::size_t fft_size = nextFastFftSize(2 * filter_length);

  const std::vector<Eigen::Vector3d>& directions = hrtf.directions();
  const Eigen::MatrixXd y = decoder_support::harmonicMatrix(order, directions);
  const Eigen::VectorXd weights = densityCompensatingWeights(directions);
  // Weighted least squares: coefficients = (Y^T W Y)^-1 Y^T W target.
  const Eigen::MatrixXd yt_w = y.transpose() * weights.asDiagonal();
  const Eigen::MatrixXd projector = (yt_w * y).ldlt().solve(yt_w);
  if (!projector.allFinite()) {
    throw InputError("the HRTF directions do not determine an order-" + std::to_string(order) + " fit");
  }

  const auto delay = static_cast<double>(bulkDelaySamples(hrtf));
  Spectra hrtfs = decoder_support::hrtfSpectra(hrtf, fft_size);
  for (std::size_t k = 0; k < hrtfs.size(); ++k) hrtfs[k] *= delayPhasor(k, fft_size, -delay);
  const Eigen::VectorXd channel_powers = decoder_support::sn3dDiffuseChannelPowers(order);
  const double bin_hz = hrtf.sampleRateHz() / static_cast<double>(fft_size);

  Spectra fitted(hrtfs.size());
  Spectra decoder(hrtfs.size());
  for (std::size_t k = 0; k < hrtfs.size(); ++k) {
    const bool magnitude_only = k > 0 && static_cast<double>(k) * bin_hz >= cutoff_hz;
    fitted[k] = magnitude_only ? Eigen::MatrixXcd(projector * withPhaseOf(hrtfs[k], y * fitted[k - 1]))
                               : Eigen::MatrixXcd(projector * hrtfs[k]);
    decoder[k] = fitted[k];
    if (options.max_re_weights) {
      decoder[k] = decoder_support::maxReTaper(order, static_cast<double>(k) * bin_hz).asDiagonal() * decoder[k];
    }
    if (options.diffuse_field_covariance) {
      constrainDiffuseFieldCovariance(decoder[k], hrtfDiffuseFieldCovariance(hrtfs[k], weights), channel_powers);
    }
    decoder[k] *= delayPhasor(k, fft_size, delay);
  }
  BinauralDecoder result;
  result.order = order;
  result.sample_rate_hz = hrtf.sampleRateHz();
  result.filters = decoder_support::filtersFromSpectra(decoder, fft_size, filter_length);
  result.method = describe(name, order, cutoff_hz, options, filter_length, hrtf);
  return result;
}

}  // namespace

BinauralDecoder makeLeastSquaresDecoder(const HrtfSet& hrtf, int order, const ShDecoderOptions& options) {
  return fitShDecoder(hrtf, order, std::numeric_limits<double>::infinity(), options, "least-squares");
}

BinauralDecoder makeMagLsDecoder(const HrtfSet& hrtf, int order, const MagLsOptions& options) {
  if (!(options.cutoff_hz >= 0.0) || !std::isfinite(options.cutoff_hz)) {
    throw InputError("the MagLS cutoff must be a finite frequency >= 0 Hz (0 for the default)");
  }
  const double cutoff_hz = options.cutoff_hz > 0.0 ? options.cutoff_hz : decoder_support::orderLimitFrequencyHz(order);
  return fitShDecoder(hrtf, order, cutoff_hz, options, "MagLS");
}

}  // namespace room_reverb::core
