#include "room_reverb/evaluation/early_energy.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

std::vector<FrequencyBand> analysableOctaves(const std::vector<double>& nominal_hz, double sample_rate_hz) {
  std::vector<FrequencyBand> bands;
  for (const FrequencyBand& band : standardBands(BandResolution::kOctave)) {
    if (std::find(nominal_hz.begin(), nominal_hz.end(), band.nominal_hz) != nominal_hz.end() &&
        band.upper_hz < 0.5 * sample_rate_hz) {
      bands.push_back(band);
    }
  }
  return bands;
}

EarlyEnergyProfile earlyEnergyProfile(const std::vector<float>& omni, double sample_rate_hz, std::size_t onset_sample,
                                      const EarlyEnergyOptions& options) {
  if (options.window_s <= 0.0 || options.window_count < 2) throw InputError("early energy: need a positive window and at least two windows");
  EarlyEnergyProfile profile;
  profile.window_s = options.window_s;
  const auto window = static_cast<std::size_t>(std::lround(options.window_s * sample_rate_hz));
  const auto lead = static_cast<std::size_t>(std::lround(options.lead_s * sample_rate_hz));
  const std::size_t start = onset_sample > lead ? onset_sample - lead : 0;
  const std::size_t span = window * static_cast<std::size_t>(options.window_count);
  // A segment with room on both sides for the zero-phase filters' rings: 10 ms before,
  // 20 ms after; filtering the whole response would cost a long FFT for nothing.
  const auto margin = static_cast<std::size_t>(0.010 * sample_rate_hz);
  const std::size_t seg_begin = start > margin ? start - margin : 0;
  const std::size_t seg_end = std::min(omni.size(), start + span + 2 * margin);
  if (seg_end <= start + window) throw InputError("early energy: the response ends before its direct sound does");
  const std::vector<float> segment(omni.begin() + static_cast<std::ptrdiff_t>(seg_begin),
                                   omni.begin() + static_cast<std::ptrdiff_t>(seg_end));

  const std::vector<FrequencyBand> bands = analysableOctaves(options.bands_hz, sample_rate_hz);
  const BandFilterBank bank(bands, sample_rate_hz);
  const std::vector<std::vector<float>> split = bank.split(segment);
  for (std::size_t b = 0; b < bands.size(); ++b) {
    std::vector<double> energy(static_cast<std::size_t>(options.window_count), 0.0);
    for (std::size_t w = 0; w < energy.size(); ++w) {
      const std::size_t from = start - seg_begin + w * window;
      const std::size_t to = std::min(split[b].size(), from + window);
      for (std::size_t n = from; n < to; ++n) energy[w] += static_cast<double>(split[b][n]) * split[b][n];
    }
    if (!(energy[0] > 0.0)) continue;  // a band with no direct sound says nothing here
    std::vector<double> level(energy.size());
    for (std::size_t w = 0; w < energy.size(); ++w) {
      level[w] = std::max(options.floor_db, 10.0 * std::log10(std::max(energy[w], 1e-300) / energy[0]));
    }
    profile.bands_hz.push_back(bands[b].nominal_hz);
    profile.level_db.push_back(level);
  }
  return profile;
}

}  // namespace room_reverb::core
