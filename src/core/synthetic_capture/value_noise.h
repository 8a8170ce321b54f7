#pragma once
// Seeded hashing and band-limited value noise for the procedural textures of the capture
// generator. Everything here is a pure function of its integer inputs and the seed, so a
// texture looks the same from both cameras, from any thread, on every run.
#include <cstdint>
#include <string>

#include "room_reverb/common/hash_mix.h"

namespace room_reverb::core::capture_detail {

inline std::uint64_t hashCombine(std::uint64_t seed, std::uint64_t value) {
  return mixBits(seed ^ (value * 0xd6e8feb86659fd93ULL + 0x632be59bd9b4e019ULL));
}

// Uniform in [0, 1) from a salt and two lattice indices: one mix of the salt and the
// indices spread by two odd constants.
// A hash of a name (a material's), for choices that must follow the name alone.
inline std::uint64_t nameHash(const std::string& name) {
  std::uint64_t h = 0x51ed270b27aa1e3dULL;
  for (const char c : name) h = hashCombine(h, static_cast<unsigned char>(c));
  return h;
}

inline double latticeUnit(std::uint64_t salt, std::int64_t i, std::int64_t j) {
  const std::uint64_t h = mixBits(salt ^ (static_cast<std::uint64_t>(i) * 0x9fb21c651e98df25ULL) ^
                                  (static_cast<std::uint64_t>(j) * 0xc2b2ae3d27d4eb4fULL));
  return unitFromBits(h);
}

// Value noise in [0, 1]: random values on the integer lattice, blended with a quintic
// fade so that the surface has continuous slope (no visible lattice grid).
double valueNoise(std::uint64_t salt, double x, double y);

// Fractal sum of value noise, centred on 0 (roughly within [-1, 1]). Octave k has lattice
// spacing base_cell_m / 2^k (x, y in metres) and weight gain^k. An octave whose cells are
// not at least two footprints wide is faded out, and dropped at one footprint: a sample
// that covers `footprint_m` of the surface cannot show finer detail without aliasing
// (which would make the stereo views disagree).
double fractalNoise(std::uint64_t salt, double x, double y, double base_cell_m, int octaves, double gain,
                    double footprint_m);

// The same, with separate cell sizes along x and y (streaks: wood grain, brushed metal).
double stretchedNoise(std::uint64_t salt, double x, double y, double cell_x_m, double cell_y_m, int octaves,
                      double gain, double footprint_m);

// 1 inside a line of half-width `half_width_m` around distance 0, 0 away from it, with a
// ramp one footprint wide (an antialiased edge for mortar, grout, seams).
double lineCoverage(double distance_m, double half_width_m, double footprint_m);

// Fractional part in [0, 1) and the integer cell of x / period.
struct Cell {
  std::int64_t index;
  double fraction;
};
Cell cellOf(double x, double period);

}  // namespace room_reverb::core::capture_detail
