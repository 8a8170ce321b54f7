#pragma once
// Acoustic materials: octave-band random-incidence absorption and scattering coefficients
// (63 Hz .. 16 kHz, the bands of audio/frequency_bands.h), and the library of named
// materials in config/materials.yaml.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {

using OctaveBandValues = std::array<double, kOctaveBandCount>;

// A set of octave bands: bit b for band b.
using BandMask = std::uint32_t;
constexpr BandMask kAllBands = (1u << kOctaveBandCount) - 1u;

// Calls f(b) for every band b in `bands`. A ray tracer's branch carries 1.7 of the nine
// bands on average over BRAS CR2's reflections once the bands' scattering has split it,
// and the others carry no energy: per-band work on them would only add or scale zeros.
template <typename F>
inline void forEachBand(BandMask bands, F&& f) {
  for (bands &= kAllBands; bands != 0; bands &= bands - 1) f(static_cast<int>(__builtin_ctz(bands)));
}

// Coefficients of the three third octaves of every octave band: [k][b] is the k-th third
// (0 lower, 1 centre, 2 upper) of octave b, e.g. [0][1] 100 Hz, [1][1] 125 Hz, [2][1] 160 Hz.
using ThirdOctaveValues = std::array<OctaveBandValues, 3>;

// The exact centres of the nine octave bands (Hz).
const OctaveBandValues& octaveCentresHz();

struct AcousticMaterial {
  std::string name;
  OctaveBandValues absorption{};  // energy absorption coefficient per octave, in [0, 1]
  OctaveBandValues scattering{};  // scattering coefficient (ISO 17497-1) per octave, in [0, 1]
  // The same per third octave, where the source gives them (BRAS CR2 does): a simulation
  // in third octaves uses them, one in octaves the octave values.
  std::optional<ThirdOctaveValues> absorption_thirds;
  std::optional<ThirdOctaveValues> scattering_thirds;
  std::string source;             // where the numbers come from
};

// The material as the k-th third of every octave sees it (0 lower, 1 centre, 2 upper): its
// third-octave coefficients where it has them, its octave ones where it has none.
AcousticMaterial thirdOctaveMaterial(const AcousticMaterial& material, int third);

// Throws InputError naming the material unless every coefficient is finite and in [0, 1].
void validateMaterial(const AcousticMaterial& material);

class MaterialLibrary {
 public:
  // Reads a library in the format of config/materials.yaml (materials: and aliases:).
  // Throws InputError for a missing or malformed file or an invalid material.
  static MaterialLibrary load(const std::string& path);
  // The project's library: $ROOM_REVERB_MATERIALS if set, else config/materials.yaml of
  // the source tree this library was built from.
  static MaterialLibrary loadDefault();
  static std::string defaultPath();

  // Adds or replaces a material (validated).
  void add(const AcousticMaterial& material);
  void addAlias(const std::string& alias, const std::string& target);
  bool contains(const std::string& name) const;
  // Resolves aliases. Unknown names are an InputError that names up to five close matches.
  const AcousticMaterial& get(const std::string& name) const;
  std::vector<std::string> names() const;  // material keys, sorted (aliases not included)
  std::size_t size() const { return materials_.size(); }

 private:
  std::map<std::string, AcousticMaterial> materials_;
  std::map<std::string, std::string> aliases_;
};

}  // namespace room_reverb::core
