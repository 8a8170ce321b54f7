#pragma once
// The noise the late field of a simulated response is made of: per Ambisonic channel, a
// sequence of signed impulses at Poisson times (the reflection density), split into the
// synthesis bands, each band divided by the root of its own smoothed energy so that a
// target energy envelope is one multiplication away.
//
// It depends on the seed and the response's shape, not on the room's energies, so every
// simulation at one seed shares it: a diagnosis synthesises dozens of candidate models of
// each pair at its seed, and the noise (a Poisson sequence, an FFT per channel and an
// inverse FFT per band) is most of the synthesis's cost. lateFieldNoise() keeps the most
// recently used noises, up to kLateFieldNoiseCacheBytes, shared between threads; a cached
// noise is the same to the bit as a freshly made one.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "room_reverb/audio/band_filter_bank.h"

namespace room_reverb::core {

struct LateFieldNoiseShape {
  std::uint32_t seed = 1;
  std::size_t frames = 0;
  std::size_t channels = 1;
  double sample_rate_hz = 48000.0;
  double room_volume_m3 = 100.0;  // the reflection density grows as 4 pi c^3 t^2 / V (Kuttruff)
  double speed_of_sound_m_s = 343.2;
  double max_event_rate_per_s = 12000.0;
  double bin_frames = 48.0;  // the energy histogram's bin; sets the smoothing window
  bool operator==(const LateFieldNoiseShape& other) const;
};

struct LateFieldNoise {
  // [band][channel][frame]: the band's noise over the root of its smoothed energy (0 where
  // that energy is 0); empty for the bands the late field leaves out.
  std::vector<std::vector<std::vector<float>>> normalised;
  std::size_t bytes() const;
};

// `wanted[t]` says which of the bank's bands are synthesised.
std::shared_ptr<const LateFieldNoise> lateFieldNoise(const LateFieldNoiseShape& shape, const BandFilterBank& bank,
                                                     const std::vector<bool>& wanted);

constexpr std::size_t kLateFieldNoiseCacheBytes = std::size_t{256} << 20;

}  // namespace room_reverb::core
