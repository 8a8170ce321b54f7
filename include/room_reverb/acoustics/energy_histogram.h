#pragma once
// Energy arriving at a receiver, per time bin and octave band, with its first-order
// directional moment (the energy-weighted sum of arrival directions, i.e. the intensity
// vector up to a constant).
#include <Eigen/Core>
#include <vector>

#include "room_reverb/acoustics/material.h"

namespace room_reverb::core {

class EnergyHistogram {
 public:
  EnergyHistogram() = default;
  EnergyHistogram(double bin_s, std::size_t bins);

  double binS() const { return bin_s_; }
  std::size_t bins() const { return bins_; }
  double durationS() const { return bin_s_ * bins_; }

  // Adds `energy` (per unit area, J/m^2 for 1 J emitted) arriving at `time_s` from
  // `direction` (unit, from the receiver towards the arrival). Out-of-range times are
  // dropped.
  void add(double time_s, int band, double energy, const Eigen::Vector3d& direction);
  // Adds energy[b] * weight[b] to every band at once (the ray tracer's hot path: one bin
  // lookup per arrival instead of one per band).
  void addBands(double time_s, const OctaveBandValues& energy, const OctaveBandValues& weight,
                const Eigen::Vector3d& direction);
  // The same for the bands in `bands` only (a ray tracer's branch carries a few of the
  // nine once the bands' scattering has split it, and the others would add zeros); the
  // one above, a straight loop, serves the path replay, whose branches carry every band.
  void addBands(double time_s, const OctaveBandValues& energy, const OctaveBandValues& weight,
                const Eigen::Vector3d& direction, BandMask bands);
  void merge(const EnergyHistogram& other);
  // Replaces one bin of one band (a continued decay, decay_continuation.h).
  void set(std::size_t bin, int band, double energy, const Eigen::Vector3d& flux);

  double energy(std::size_t bin, int band) const { return energy_[bin * kOctaveBandCount + band]; }
  Eigen::Vector3d flux(std::size_t bin, int band) const;
  // Sum over bins of one band.
  double totalEnergy(int band) const;

 private:
  double bin_s_ = 0.001;
  std::size_t bins_ = 0;
  std::vector<double> energy_;  // [bin][band]
  std::vector<double> flux_;    // [bin][band][xyz]
};

}  // namespace room_reverb::core
