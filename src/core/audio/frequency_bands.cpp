#include "room_reverb/audio/frequency_bands.h"

#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

std::vector<FrequencyBand> makeBands(const std::vector<double>& nominal, int first_index,
                                     int bands_per_octave) {
  std::vector<FrequencyBand> bands;
  const double half_width = 1.0 / (2.0 * bands_per_octave);
  for (std::size_t i = 0; i < nominal.size(); ++i) {
    const int k = first_index + static_cast<int>(i);
    const double center = 1000.0 * std::pow(2.0, static_cast<double>(k) / bands_per_octave);
    bands.push_back({nominal[i], center, center * std::pow(2.0, -half_width),
                     center * std::pow(2.0, half_width)});
  }
  return bands;
}

}  // namespace

BandResolution parseBandResolution(const std::string& name) {
  if (name == "octave" || name.empty()) return BandResolution::kOctave;
  if (name == "third" || name == "third-octave") return BandResolution::kThirdOctave;
  throw InputError("unknown band resolution '" + name + "' (use octave or third)");
}

std::string toString(BandResolution resolution) {
  return resolution == BandResolution::kOctave ? "octave" : "third";
}

std::vector<FrequencyBand> standardBands(BandResolution resolution) {
  if (resolution == BandResolution::kOctave) {
    return makeBands({63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000}, -4, 1);
  }
  return makeBands({20,   25,   31.5, 40,   50,   63,   80,    100,   125,   160,   200,
                    250,  315,  400,  500,  630,  800,  1000,  1250,  1600,  2000,  2500,
                    3150, 4000, 5000, 6300, 8000, 10000, 12500, 16000, 20000},
                   -17, 3);
}

std::vector<FrequencyBand> thirdsOfTheOctaves() {
  const std::vector<FrequencyBand> thirds = standardBands(BandResolution::kThirdOctave);
  const std::vector<FrequencyBand> octaves = standardBands(BandResolution::kOctave);
  std::vector<FrequencyBand> bands;
  for (const FrequencyBand& third : thirds) {
    if (third.center_hz > octaves.front().lower_hz && third.center_hz < octaves.back().upper_hz) bands.push_back(third);
  }
  return bands;
}

}  // namespace room_reverb::core
