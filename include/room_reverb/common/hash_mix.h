#pragma once
// Counter-based random numbers: a 64-bit avalanche mix and its top bits as a uniform
// number. Anything drawn this way is a pure function of its integer inputs, so it is the
// same from any thread, in any order, on every run (the capture generator's textures, the
// ray tracer's common random numbers).
#include <cstdint>

namespace room_reverb::core {

// The splitmix64 finaliser (Steele, Lea and Flood 2014): neighbouring inputs give
// unrelated outputs. Inline: the textures and the ray tracer call it millions of times.
inline std::uint64_t mixBits(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Uniform in [0, 1) from the top 53 bits of a mixed value.
inline double unitFromBits(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

}  // namespace room_reverb::core
