#pragma once
// Synthetic impulse responses with known truth, for the tests.
#include <cstdint>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::test {

constexpr double kFs = 48000.0;

// Gaussian white noise, unit variance, deterministic for a seed.
std::vector<float> whiteNoise(std::size_t length, std::uint32_t seed);

// Noise whose mean-square envelope decays by 60 dB in `t60_s`, starting at `onset`
// with mean-square 1.
std::vector<float> exponentialDecayNoise(std::size_t length, double t60_s, std::size_t onset,
                                         std::uint32_t seed);

// Random-sign pulses whose squared value follows exp(-delta t) exactly (delta from t60_s),
// so energy ratios match their closed forms with no noise fluctuation.
std::vector<float> exactEnergyDecay(std::size_t length, double t60_s, std::size_t onset,
                                    std::uint32_t seed);

// A sum over bands: band b gets its own noise, limited to the central half of the band
// (so no other band's analysis sees it), decaying with t60_s[b]. Each band carries the
// same mean-square level at the onset.
std::vector<float> bandwiseDecayNoise(std::size_t length, const std::vector<core::FrequencyBand>& bands,
                                      const std::vector<double>& t60_s, std::size_t onset,
                                      std::uint32_t seed);

// Like bandwiseDecayNoise, but each band's noise is a random frequency modulation: a
// tone whose frequency wanders randomly (smooth random modulation) over the central half
// of the band. Its envelope is constant, unlike Gaussian noise's Rayleigh envelope, so the
// decay curve of each band is the planted exponential without the 4-10 % statistical
// scatter of T20 that one Gaussian realisation has in an octave band (ISO 3382-2 A.2).
std::vector<float> bandwiseDecayRandomFm(std::size_t length, const std::vector<core::FrequencyBand>& bands,
                                         const std::vector<double>& t60_s, std::size_t onset,
                                         std::uint32_t seed);

// Adds stationary white noise at `level_db` below mean-square 1 (the decays' start level).
void addNoiseFloor(std::vector<float>& signal, double level_db, std::uint32_t seed);

// Energy (sum of squares) of a signal.
double energy(const std::vector<float>& x);

}  // namespace room_reverb::test
