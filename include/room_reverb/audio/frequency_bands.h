#pragma once
// Octave and third-octave bands (IEC 61260-1, base-2 exact centres around 1 kHz).
#include <string>
#include <vector>

namespace room_reverb::core {

enum class BandResolution { kOctave, kThirdOctave };

// "octave" or "third"; anything else is an InputError.
BandResolution parseBandResolution(const std::string& name);
std::string toString(BandResolution resolution);

struct FrequencyBand {
  double nominal_hz;  // the label (63, 125, ... or 20, 25, 31.5, ...)
  double center_hz;   // exact: 1000 * 2^(k/b)
  double lower_hz;    // center * 2^(-1/(2b))
  double upper_hz;    // center * 2^(+1/(2b))
};

// The project's standard sets: nine octaves 63 Hz - 16 kHz (the S3A renderer's sub-bands,
// DESIGN.md) and 31 third octaves 20 Hz - 20 kHz (the BRAS material data's bands).
std::vector<FrequencyBand> standardBands(BandResolution resolution);

// Number of the standard octave bands (63 Hz .. 16 kHz).
constexpr int kOctaveBandCount = 9;

// The 27 thirds of the nine standard octaves, 50 Hz - 20 kHz: band t is the (t % 3)-th
// third (lower, centre, upper) of octave t / 3, as a simulation in third octaves orders
// its bands (AcousticScene::thirdOctaveBands).
std::vector<FrequencyBand> thirdsOfTheOctaves();

}  // namespace room_reverb::core
