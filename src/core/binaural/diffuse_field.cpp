#include "room_reverb/binaural/diffuse_field.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>

#include "room_reverb/audio/fft.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/common/error.h"
#include "sphere_quadrature.h"

namespace room_reverb::core {
namespace {

// Bin spacing fine enough to put a few bins into the 63 Hz octave (44-88 Hz).
constexpr double kMaxBinSpacingHz = 12.0;
// A centre within this many octaves of a standard octave band's is that band.
constexpr double kSameBandOctaves = 1.0 / 6.0;

FrequencyBand octaveBandAround(double centre_hz) {
  if (!(centre_hz > 0.0) || !std::isfinite(centre_hz)) {
    std::ostringstream os;
    os << "octave band centre " << centre_hz << " Hz is not a positive frequency";
    throw InputError(os.str());
  }
  for (const FrequencyBand& band : standardBands(BandResolution::kOctave)) {
    if (std::abs(std::log2(centre_hz / band.center_hz)) < kSameBandOctaves) return band;
  }
  return {centre_hz, centre_hz, centre_hz / std::sqrt(2.0), centre_hz * std::sqrt(2.0)};
}

}  // namespace

DiffuseFieldSpectrum weightedPairSpectrum(const std::vector<const Hrir*>& pairs, const std::vector<double>& weights,
                                          std::size_t fft_size, double sample_rate_hz) {
  if (pairs.size() != weights.size()) throw InputError("diffuse field: one weight per ear pair is needed");
  RealFft fft(fft_size);
  const std::size_t bins = fft.spectrumSize();
  DiffuseFieldSpectrum result;
  result.bin_spacing_hz = sample_rate_hz / static_cast<double>(fft_size);
  result.power_left.assign(bins, 0.0);
  result.power_right.assign(bins, 0.0);
  std::vector<std::complex<double>> cross(bins, 0.0);
  std::vector<float> padded(fft_size, 0.0f);
  std::vector<std::complex<float>> left(bins), right(bins);
  for (std::size_t d = 0; d < pairs.size(); ++d) {
    const Hrir& pair = *pairs[d];
    if (pair.left.size() > fft_size || pair.right.size() > fft_size) {
      throw InputError("diffuse field: an ear filter is longer than the FFT grid");
    }
    std::fill(padded.begin(), padded.end(), 0.0f);
    std::copy(pair.left.begin(), pair.left.end(), padded.begin());
    fft.forward(padded.data(), left.data());
    std::fill(padded.begin(), padded.end(), 0.0f);
    std::copy(pair.right.begin(), pair.right.end(), padded.begin());
    fft.forward(padded.data(), right.data());
    for (std::size_t k = 0; k < bins; ++k) {
      const std::complex<double> l(left[k]), r(right[k]);
      cross[k] += weights[d] * l * std::conj(r);
      result.power_left[k] += weights[d] * std::norm(l);
      result.power_right[k] += weights[d] * std::norm(r);
    }
  }
  result.coherence.resize(bins);
  for (std::size_t k = 0; k < bins; ++k) {
    const double auto_product = std::sqrt(result.power_left[k] * result.power_right[k]);
    // Where neither ear receives anything there is no coherence to speak of.
    result.coherence[k] = auto_product > 0.0 ? cross[k].real() / auto_product : 0.0;
  }
  return result;
}

DiffuseFieldSpectrum diffuseFieldSpectrum(const HrtfSet& hrtfs) {
  const auto fine_size = static_cast<std::size_t>(std::ceil(hrtfs.sampleRateHz() / kMaxBinSpacingHz));
  const Eigen::VectorXd solid_angles = densityCompensatingWeights(hrtfs.directions());
  std::vector<const Hrir*> pairs;
  std::vector<double> weights;
  for (std::size_t d = 0; d < hrtfs.size(); ++d) {
    pairs.push_back(&hrtfs.hrir(d));
    weights.push_back(solid_angles[static_cast<Eigen::Index>(d)]);
  }
  return weightedPairSpectrum(pairs, weights, nextFastFftSize(std::max(2 * hrtfs.length(), fine_size)),
                              hrtfs.sampleRateHz());
}

std::vector<double> diffuseFieldCoherence(const HrtfSet& hrtfs,
                                          const std::vector<double>& band_centres_hz) {
  return diffuseFieldCoherence(diffuseFieldSpectrum(hrtfs), band_centres_hz);
}

std::vector<double> diffuseFieldCoherence(const DiffuseFieldSpectrum& spectrum,
                                          const std::vector<double>& band_centres_hz) {
  std::vector<double> result;
  for (double centre : band_centres_hz) {
    const FrequencyBand band = octaveBandAround(centre);
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t k = 1; k < spectrum.coherence.size(); ++k) {
      const double f = static_cast<double>(k) * spectrum.bin_spacing_hz;
      if (f >= band.lower_hz && f < band.upper_hz) {
        sum += spectrum.coherence[k];
        ++count;
      }
    }
    if (count == 0) {
      const double nyquist = spectrum.bin_spacing_hz * static_cast<double>(spectrum.coherence.size() - 1);
      std::ostringstream os;
      os << "the octave band around " << centre << " Hz holds no frequency of the HRTF spectrum"
         << " (bins every " << spectrum.bin_spacing_hz << " Hz up to " << nyquist
         << " Hz): choose centres within that range";
      throw InputError(os.str());
    }
    result.push_back(sum / static_cast<double>(count));
  }
  return result;
}

}  // namespace room_reverb::core
