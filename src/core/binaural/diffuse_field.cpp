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

DiffuseFieldSpectrum diffuseFieldSpectrum(const HrtfSet& hrtfs) {
  const std::size_t length = hrtfs.length();
  const auto fine_size = static_cast<std::size_t>(std::ceil(hrtfs.sampleRateHz() / kMaxBinSpacingHz));
  RealFft fft(nextFastFftSize(std::max(2 * length, fine_size)));
  const std::size_t bins = fft.spectrumSize();
  const Eigen::VectorXd weights = densityCompensatingWeights(hrtfs.directions());

  std::vector<std::complex<double>> cross(bins, 0.0);
  DiffuseFieldSpectrum result;
  result.bin_spacing_hz = hrtfs.sampleRateHz() / static_cast<double>(fft.size());
  result.power_left.assign(bins, 0.0);
  result.power_right.assign(bins, 0.0);
  std::vector<float> padded(fft.size(), 0.0f);
  std::vector<std::complex<float>> left(bins);
  std::vector<std::complex<float>> right(bins);
  for (std::size_t d = 0; d < hrtfs.size(); ++d) {
    std::copy(hrtfs.hrir(d).left.begin(), hrtfs.hrir(d).left.end(), padded.begin());
    fft.forward(padded.data(), left.data());
    std::copy(hrtfs.hrir(d).right.begin(), hrtfs.hrir(d).right.end(), padded.begin());
    fft.forward(padded.data(), right.data());
    const double w = weights[static_cast<Eigen::Index>(d)];
    for (std::size_t k = 0; k < bins; ++k) {
      const std::complex<double> l(left[k]);
      const std::complex<double> r(right[k]);
      cross[k] += w * l * std::conj(r);
      result.power_left[k] += w * std::norm(l);
      result.power_right[k] += w * std::norm(r);
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
