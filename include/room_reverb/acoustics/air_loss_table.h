#pragma once
// The air's energy loss exp(-m d) per octave band over a path of d metres, as the ray
// tracer and the path replay need it at every arrival. One exp per band and arrival costs
// more than the rest of a deposit, so the loss is read from a table of exp(-m k L) at
// whole histogram bins (L = c bin_s) and the remainder x = m (d - k L) <= m L is taken by
// a 5-term series of exp(-x), exact to 1e-9 for the air of ISO 9613-1 and bins up to
// several milliseconds.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "room_reverb/acoustics/material.h"

namespace room_reverb::core {

class AirLossTable {
 public:
  AirLossTable(const OctaveBandValues& attenuation_per_m, double bin_m, std::size_t bins)
      : attenuation_per_m_(attenuation_per_m), bin_m_(bin_m), upper_((bins + 2) * kOctaveBandCount),
        lower_((bins + 2) * kOctaveBandCount) {
    for (std::size_t k = 0; k < bins + 2; ++k) {
      for (int b = 0; b < kOctaveBandCount; ++b) {
        upper_[k * kOctaveBandCount + b] = std::exp(-attenuation_per_m[b] * (static_cast<double>(k) * bin_m));
        lower_[k * kOctaveBandCount + b] = std::exp(-attenuation_per_m[b] * (static_cast<double>(k + 1) * bin_m));
      }
    }
  }

  // exp(-m_b d) times `factor` for every band b.
  void loss(double distance_m, double factor, OctaveBandValues& out) const {
    const std::size_t k = bin(distance_m);
    const double* upper = &upper_[k * kOctaveBandCount];
    const double rest = distance_m - static_cast<double>(k) * bin_m_;
    for (int b = 0; b < kOctaveBandCount; ++b) {
      out[b] = factor * upper[b] * expSeries(attenuation_per_m_[b] * rest);
    }
  }

  // The same for the bands in `bands` only (the others are left as they are).
  void loss(double distance_m, double factor, OctaveBandValues& out, BandMask bands) const {
    const std::size_t k = bin(distance_m);
    const double* upper = &upper_[k * kOctaveBandCount];
    const double rest = distance_m - static_cast<double>(k) * bin_m_;
    forEachBand(bands, [&](int b) { out[b] = factor * upper[b] * expSeries(attenuation_per_m_[b] * rest); });
  }

  // Per band, exp(-m_b d) from below: the table's value at the end of d's bin.
  const double* lowerBound(double distance_m) const { return &lower_[bin(distance_m) * kOctaveBandCount]; }
  // Per band, exp(-m_b k L) at the start of bin k.
  const double* atBin(std::size_t k) const {
    return &upper_[std::min(k, upper_.size() / kOctaveBandCount - 2) * kOctaveBandCount];
  }

  const OctaveBandValues& attenuationPerM() const { return attenuation_per_m_; }

 private:
  // exp(-x) for 0 <= x <= m L, by its series to the fourth power.
  static double expSeries(double x) { return 1.0 - x * (1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0)))); }

  std::size_t bin(double distance_m) const {
    return std::min(static_cast<std::size_t>(std::max(0.0, distance_m) / bin_m_), upper_.size() / kOctaveBandCount - 2);
  }

  OctaveBandValues attenuation_per_m_;
  double bin_m_;
  std::vector<double> upper_, lower_;  // [k][band]: exp(-m k L), exp(-m (k+1) L)
};

}  // namespace room_reverb::core
