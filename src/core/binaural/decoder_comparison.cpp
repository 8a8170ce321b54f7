#include "room_reverb/binaural/decoder_comparison.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include "decoder_support.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/binaural/binaural_cues.h"
#include "room_reverb/binaural/loudspeaker_layout.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

std::vector<FrequencyBand> comparisonBands() {
  std::vector<FrequencyBand> bands;
  for (const auto& band : standardBands(BandResolution::kOctave)) {
    if (band.nominal_hz >= 500.0 && band.nominal_hz <= 8000.0) bands.push_back(band);
  }
  return bands;
}

// The measured directions nearest to a near-uniform set, each once.
std::vector<std::size_t> comparisonDirections(const HrtfSet& hrtf, std::size_t count) {
  std::vector<std::size_t> indices;
  for (const auto& direction : fibonacciLayout(count)) indices.push_back(hrtf.nearest(direction));
  std::sort(indices.begin(), indices.end());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  return indices;
}

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

// Mean power of one ear over the bins of a band.
double bandPower(const std::vector<double>& power, double bin_spacing_hz, const FrequencyBand& band) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 1; k < power.size(); ++k) {
    const double f = static_cast<double>(k) * bin_spacing_hz;
    if (f >= band.lower_hz && f < band.upper_hz) {
      sum += power[k];
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

void compareDiffuseFields(const BinauralDecoder& decoder, const HrtfSet& hrtf, const std::vector<FrequencyBand>& bands,
                          DecoderComparison& result) {
  const DiffuseFieldSpectrum direct = diffuseFieldSpectrum(hrtf);
  const DiffuseFieldSpectrum decoded = decoderDiffuseFieldSpectrum(decoder, direct);
  const std::vector<double> coherence_direct = diffuseFieldCoherence(direct, result.band_centres_hz);
  const std::vector<double> coherence_decoded = diffuseFieldCoherence(decoded, result.band_centres_hz);
  const double spacing = direct.bin_spacing_hz;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const double left_db = 10.0 * std::log10(bandPower(decoded.power_left, spacing, bands[b]) /
                                             bandPower(direct.power_left, spacing, bands[b]));
    const double right_db = 10.0 * std::log10(bandPower(decoded.power_right, spacing, bands[b]) /
                                              bandPower(direct.power_right, spacing, bands[b]));
    result.diffuse_level_error_db.push_back(0.5 * (std::abs(left_db) + std::abs(right_db)));
    result.diffuse_coherence_error.push_back(std::abs(coherence_decoded[b] - coherence_direct[b]));
  }
  result.diffuse_level_error_db_mean = mean(result.diffuse_level_error_db);
  result.diffuse_coherence_error_mean = mean(result.diffuse_coherence_error);
}

}  // namespace

DiffuseFieldSpectrum decoderDiffuseFieldSpectrum(const BinauralDecoder& decoder, const DiffuseFieldSpectrum& like) {
  const auto fft_size = static_cast<std::size_t>(std::lround(decoder.sample_rate_hz / like.bin_spacing_hz));
  const std::size_t length = decoder.filters.empty() ? 0 : decoder.filters.front().left.size();
  if (decoder.order < 1 || decoder.order > kMaxAmbisonicOrder ||
      decoder.filters.size() != static_cast<std::size_t>(ambisonicChannelCount(decoder.order)) || fft_size < length ||
      fft_size / 2 + 1 != like.coherence.size()) {
    throw InputError("the decoder's filters do not fit the diffuse-field spectrum's frequency grid");
  }
  const Eigen::VectorXd powers = decoder_support::sn3dDiffuseChannelPowers(decoder.order);
  std::vector<const Hrir*> pairs;
  std::vector<double> weights;
  for (std::size_t c = 0; c < decoder.filters.size(); ++c) {
    pairs.push_back(&decoder.filters[c]);
    weights.push_back(powers(static_cast<Eigen::Index>(c)));
  }
  return weightedPairSpectrum(pairs, weights, fft_size, decoder.sample_rate_hz);
}

DecoderComparison compareDecoderToHrtf(const BinauralDecoder& decoder, const HrtfSet& hrtf,
                                       std::size_t direction_count) {
  if (direction_count < 21 || direction_count > 10000) {
    throw InputError("a decoder comparison needs 21 to 10000 directions");
  }
  if (decoder.sample_rate_hz != hrtf.sampleRateHz()) {
    throw InputError("the decoder and the HRTF set have different sample rates; make the decoder from this set");
  }
  const double rate = hrtf.sampleRateHz();
  const std::vector<FrequencyBand> bands = comparisonBands();
  DecoderComparison result;
  for (const auto& band : bands) result.band_centres_hz.push_back(band.nominal_hz);
  result.ild_error_db.assign(bands.size(), 0.0);

  const std::vector<std::size_t> indices = comparisonDirections(hrtf, direction_count);
  double itd_error_sum_us = 0.0;
  for (const std::size_t i : indices) {
    const Hrir& direct = hrtf.hrir(i);
    const Hrir decoded = decodedPlaneWaveResponse(decoder, hrtf.direction(i));
    const std::vector<double> ild_direct = interauralLevelDifferencesDb(direct, rate, bands);
    const std::vector<double> ild_decoded = interauralLevelDifferencesDb(decoded, rate, bands);
    for (std::size_t b = 0; b < bands.size(); ++b) result.ild_error_db[b] += std::abs(ild_decoded[b] - ild_direct[b]);
    const double itd_error_us =
        1e6 * std::abs(interauralTimeDifferenceS(decoded, rate) - interauralTimeDifferenceS(direct, rate));
    itd_error_sum_us += itd_error_us;
    result.itd_error_us_max = std::max(result.itd_error_us_max, itd_error_us);
  }
  const auto n = static_cast<double>(indices.size());
  for (double& error : result.ild_error_db) error /= n;
  result.ild_error_db_mean = mean(result.ild_error_db);
  result.itd_error_us = itd_error_sum_us / n;
  result.direction_count = indices.size();
  compareDiffuseFields(decoder, hrtf, bands, result);
  return result;
}

}  // namespace room_reverb::core
