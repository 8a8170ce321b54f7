#include "room_reverb/evaluation/early_direction.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/common/error.h"
#include "room_reverb/evaluation/early_energy.h"
#include "room_reverb/rsao/direction_of_arrival.h"

namespace room_reverb::core {
namespace {

const std::array<Eigen::Vector3d, kEarlyDirections> kDirections{
    Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
    -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ()};

}  // namespace

EarlyDirectionProfile earlyDirectionProfile(const AudioBuffer& ambix, std::size_t onset_sample,
                                            const EarlyDirectionOptions& options) {
  if (ambix.channelCount() < 4) throw InputError("early directions: need a first-order B-format response (4 channels)");
  if (!(options.start_s > 0.0) || !(options.end_s > options.start_s)) {
    throw InputError("early directions: the window must start after the direct sound and not be empty");
  }
  const double fs = ambix.sample_rate_hz;
  const std::size_t from = onset_sample + static_cast<std::size_t>(std::lround(options.start_s * fs));
  const std::size_t to = onset_sample + static_cast<std::size_t>(std::lround(options.end_s * fs));
  if (to > ambix.frameCount()) throw InputError("early directions: the response ends before the early reflections do");
  // A segment with 10 ms on both sides for the zero-phase filters' rings.
  const auto margin = static_cast<std::size_t>(0.010 * fs);
  const std::size_t seg_begin = from > margin ? from - margin : 0;
  const std::size_t seg_end = std::min(ambix.frameCount(), to + margin);

  const std::vector<FrequencyBand> bands = analysableOctaves(options.bands_hz, fs);
  const BandFilterBank bank(bands, fs);
  std::vector<std::vector<std::vector<float>>> split;  // [channel][band][sample]
  for (std::size_t c = 0; c < 4; ++c) {
    const auto& channel = ambix.channels[c];
    split.push_back(bank.split(std::vector<float>(channel.begin() + static_cast<std::ptrdiff_t>(seg_begin),
                                                  channel.begin() + static_cast<std::ptrdiff_t>(seg_end))));
  }
  SampleWindow window;
  window.first = from - seg_begin;
  window.weights.assign(to - from, 1.0);

  EarlyDirectionProfile profile;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    AudioBuffer band;
    band.sample_rate_hz = fs;
    for (std::size_t c = 0; c < 4; ++c) band.channels.push_back(split[c][b]);
    const CardioidSteeringStatistics stats = steeringStatistics(band, window);
    if (!(stats.energy_w > 0.0)) continue;
    std::array<double, kEarlyDirections> level{};
    for (std::size_t d = 0; d < kEarlyDirections; ++d) {
      level[d] = 10.0 * std::log10(std::max(stats.steeredEnergy(kDirections[d]), 1e-30 * stats.energy_w) / stats.energy_w);
    }
    profile.bands_hz.push_back(bands[b].nominal_hz);
    profile.level_db.push_back(level);
  }
  return profile;
}

}  // namespace room_reverb::core
