#include "room_reverb/acoustics/energy_histogram.h"

#include <cmath>
#include <stdexcept>

namespace room_reverb::core {

EnergyHistogram::EnergyHistogram(double bin_s, std::size_t bins)
    : bin_s_(bin_s), bins_(bins), energy_(bins * kOctaveBandCount, 0.0), flux_(bins * kOctaveBandCount * 3, 0.0) {
  if (!(bin_s > 0.0)) throw std::invalid_argument("histogram bin width must be positive");
}

void EnergyHistogram::add(double time_s, int band, double energy, const Eigen::Vector3d& direction) {
  if (!(time_s >= 0.0)) return;
  const auto bin = static_cast<std::size_t>(time_s / bin_s_);
  if (bin >= bins_) return;
  const std::size_t index = bin * kOctaveBandCount + static_cast<std::size_t>(band);
  energy_[index] += energy;
  for (int k = 0; k < 3; ++k) flux_[3 * index + k] += energy * direction[k];
}

void EnergyHistogram::addBands(double time_s, const OctaveBandValues& energy, const OctaveBandValues& weight,
                               const Eigen::Vector3d& direction) {
  if (!(time_s >= 0.0)) return;
  const auto bin = static_cast<std::size_t>(time_s / bin_s_);
  if (bin >= bins_) return;
  double* e = &energy_[bin * kOctaveBandCount];
  double* f = &flux_[3 * bin * kOctaveBandCount];
  for (int b = 0; b < kOctaveBandCount; ++b) {
    const double v = energy[b] * weight[b];
    e[b] += v;
    for (int k = 0; k < 3; ++k) f[3 * b + k] += v * direction[k];
  }
}

void EnergyHistogram::addBands(double time_s, const OctaveBandValues& energy, const OctaveBandValues& weight,
                               const Eigen::Vector3d& direction, BandMask bands) {
  if (!(time_s >= 0.0)) return;
  const auto bin = static_cast<std::size_t>(time_s / bin_s_);
  if (bin >= bins_) return;
  double* e = &energy_[bin * kOctaveBandCount];
  double* f = &flux_[3 * bin * kOctaveBandCount];
  forEachBand(bands, [&](int b) {
    const double v = energy[b] * weight[b];
    e[b] += v;
    for (int k = 0; k < 3; ++k) f[3 * b + k] += v * direction[k];
  });
}

void EnergyHistogram::merge(const EnergyHistogram& other) {
  if (other.bins_ != bins_ || other.bin_s_ != bin_s_) throw std::invalid_argument("histograms differ in shape");
  for (std::size_t i = 0; i < energy_.size(); ++i) energy_[i] += other.energy_[i];
  for (std::size_t i = 0; i < flux_.size(); ++i) flux_[i] += other.flux_[i];
}

void EnergyHistogram::set(std::size_t bin, int band, double energy, const Eigen::Vector3d& flux) {
  if (bin >= bins_) throw std::invalid_argument("histogram bin out of range");
  const std::size_t index = bin * kOctaveBandCount + static_cast<std::size_t>(band);
  energy_[index] = energy;
  for (int k = 0; k < 3; ++k) flux_[3 * index + k] = flux[k];
}

Eigen::Vector3d EnergyHistogram::flux(std::size_t bin, int band) const {
  const std::size_t index = 3 * (bin * kOctaveBandCount + static_cast<std::size_t>(band));
  return {flux_[index], flux_[index + 1], flux_[index + 2]};
}

double EnergyHistogram::totalEnergy(int band) const {
  double sum = 0.0;
  for (std::size_t bin = 0; bin < bins_; ++bin) sum += energy(bin, band);
  return sum;
}

}  // namespace room_reverb::core
