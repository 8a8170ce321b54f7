#include "room_reverb/acoustics/late_field_noise.h"

#include <algorithm>
#include <cmath>
#include <list>
#include <mutex>
#include <random>
#include <utility>

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Probability of an event per sample at time t: the reflection density 4 pi c^3 t^2 / V
// (Kuttruff), capped.
double eventProbability(double t, const LateFieldNoiseShape& s) {
  const double growth = 4.0 * kPi * std::pow(s.speed_of_sound_m_s, 3) / s.room_volume_m3;
  return std::min(s.max_event_rate_per_s, growth * t * t) / s.sample_rate_hz;
}

// Signed unit impulses at Poisson times with that density.
std::vector<float> poissonSequence(const LateFieldNoiseShape& s, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<float> x(s.frames, 0.0f);
  for (std::size_t n = 0; n < s.frames; ++n) {
    if (u(rng) < eventProbability(n / s.sample_rate_hz, s)) x[n] = u(rng) < 0.5 ? -1.0f : 1.0f;
  }
  return x;
}

// The band signal over the root of its realised energy per sample, averaged over a centred
// window. The late field is scaled by target / realised energy: averaging over a few of
// the band's correlation times keeps that gain smooth (no spreading into other bands)
// while still taking out the noise's own slow level wander, which would otherwise scatter
// the decay time from one seed to the next (the ISO 3382-2 scatter of a single noise
// realisation).
std::vector<float> normalisedBySmoothedEnergy(const std::vector<float>& x, std::size_t window) {
  std::vector<double> prefix(x.size() + 1, 0.0);
  for (std::size_t n = 0; n < x.size(); ++n) prefix[n + 1] = prefix[n] + static_cast<double>(x[n]) * x[n];
  std::vector<float> out(x.size(), 0.0f);
  const std::size_t half = window / 2;
  for (std::size_t n = 0; n < x.size(); ++n) {
    const std::size_t first = n > half ? n - half : 0;
    const std::size_t last = std::min(x.size(), n + half + 1);
    const double realised = (prefix[last] - prefix[first]) / static_cast<double>(last - first);
    if (realised > 0.0) out[n] = static_cast<float>(x[n] / std::sqrt(realised));
  }
  return out;
}

std::shared_ptr<const LateFieldNoise> makeNoise(const LateFieldNoiseShape& shape, const BandFilterBank& bank,
                                                const std::vector<bool>& wanted) {
  auto noise = std::make_shared<LateFieldNoise>();
  // One independent sequence per channel, drawn in channel order from one generator.
  std::mt19937_64 rng(shape.seed);
  std::vector<BandFilterBank::PaddedSpectrum> spectra(shape.channels);
  for (std::size_t c = 0; c < shape.channels; ++c) spectra[c] = bank.analyse(poissonSequence(shape, rng));
  noise->normalised.resize(bank.bands().size());
  for (std::size_t t = 0; t < bank.bands().size(); ++t) {
    if (t >= wanted.size() || !wanted[t]) continue;
    const FrequencyBand& band = bank.bands()[t];
    const auto window = static_cast<std::size_t>(
        std::max(5.0 * shape.bin_frames, 4.0 * shape.sample_rate_hz / (band.upper_hz - band.lower_hz)));
    noise->normalised[t].resize(shape.channels);
    for (std::size_t c = 0; c < shape.channels; ++c) {
      noise->normalised[t][c] = normalisedBySmoothedEnergy(bank.extract(spectra[c], t), window);
    }
  }
  return noise;
}

struct CachedNoise {
  LateFieldNoiseShape shape;
  std::vector<bool> wanted;
  std::vector<double> band_centres_hz;
  std::shared_ptr<const LateFieldNoise> noise;
  std::size_t uses = 1;
};

}  // namespace

bool LateFieldNoiseShape::operator==(const LateFieldNoiseShape& o) const {
  return seed == o.seed && frames == o.frames && channels == o.channels && sample_rate_hz == o.sample_rate_hz &&
         room_volume_m3 == o.room_volume_m3 && speed_of_sound_m_s == o.speed_of_sound_m_s &&
         max_event_rate_per_s == o.max_event_rate_per_s && bin_frames == o.bin_frames;
}

std::size_t LateFieldNoise::bytes() const {
  std::size_t n = 0;
  for (const auto& band : normalised) {
    for (const auto& channel : band) n += channel.size() * sizeof(float);
  }
  return n;
}

std::shared_ptr<const LateFieldNoise> lateFieldNoise(const LateFieldNoiseShape& shape, const BandFilterBank& bank,
                                                     const std::vector<bool>& wanted) {
  static std::mutex mutex;
  static std::list<CachedNoise> cache;  // most recently used first
  static std::size_t cached_bytes = 0;
  // The bank is part of the key: octave and third-octave synthesis share seeds.
  std::vector<double> centres;
  for (const FrequencyBand& band : bank.bands()) centres.push_back(band.center_hz);
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (auto it = cache.begin(); it != cache.end(); ++it) {
      if (it->shape == shape && it->wanted == wanted && it->band_centres_hz == centres) {
        ++it->uses;
        cache.splice(cache.begin(), cache, it);
        return cache.front().noise;
      }
    }
  }
  // Made outside the lock: two threads wanting the same new noise both make it (the same
  // to the bit) rather than one waiting on the other's FFTs.
  std::shared_ptr<const LateFieldNoise> noise = makeNoise(shape, bank, wanted);
  const std::size_t bytes = noise->bytes();
  if (bytes > kLateFieldNoiseCacheBytes) return noise;
  const std::lock_guard<std::mutex> lock(mutex);
  for (const CachedNoise& c : cache) {
    if (c.shape == shape && c.wanted == wanted && c.band_centres_hz == centres) return c.noise;
  }
  // The least used goes first, of those the least recently used: a diagnosis comes back to
  // each pair's base seed for every candidate and to each noise seed a few times, and in
  // that cycle a plain least-recently-used order would drop the base seeds.
  while (!cache.empty() && cached_bytes + bytes > kLateFieldNoiseCacheBytes) {
    auto victim = std::prev(cache.end());
    for (auto it = victim; it != cache.begin();) {
      --it;
      if (it->uses < victim->uses) victim = it;
    }
    cached_bytes -= victim->noise->bytes();
    cache.erase(victim);
  }
  cache.push_front({shape, wanted, centres, noise});
  cached_bytes += bytes;
  return noise;
}

}  // namespace room_reverb::core
