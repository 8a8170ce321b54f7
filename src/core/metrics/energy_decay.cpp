#include "room_reverb/metrics/energy_decay.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace room_reverb::core {

EnergyDecay::EnergyDecay(const std::vector<float>& signal, std::size_t onset, double fs) : fs_(fs) {
  std::vector<double> energy;
  energy.reserve(signal.size() > onset ? signal.size() - onset : 0);
  for (std::size_t n = onset; n < signal.size(); ++n) energy.push_back(static_cast<double>(signal[n]) * signal[n]);
  integrate(energy);
}

EnergyDecay::EnergyDecay(const std::vector<double>& energy, std::size_t onset, double fs) : fs_(fs) {
  integrate(onset == 0 ? energy
                       : std::vector<double>(energy.begin() + static_cast<std::ptrdiff_t>(std::min(onset, energy.size())),
                                             energy.end()));
}

void EnergyDecay::integrate(const std::vector<double>& energy) {
  const double fs = fs_;
  lundeby_ = lundebyTruncation(energy, fs);
  if (!lundeby_.valid) return;

  // Backward integration up to the crosspoint of the energy less the noise power (its
  // expectation; Chu's subtraction, which ISO 3382-1 5.3.3 allows beside truncation),
  // so the noise between a time and the crosspoint does not lift the curve. The energy
  // past the crosspoint comes from the decay line.
  const std::size_t end = lundeby_.crosspoint;
  const double noise = lundeby_.noise_power;
  // Sums in samples, scaled once at the end: a division per sample cost more than the rest
  // of the curve.
  const double inv_fs = 1.0 / fs;
  backward_.assign(end + 1, 0.0);
  double moment = 0.0;
  for (std::size_t n = end; n-- > 0;) {
    const double e = energy[n] - noise;
    backward_[n] = backward_[n + 1] + e * inv_fs;
    moment += static_cast<double>(n) * e;
  }
  first_moment_ = moment * inv_fs * inv_fs;
  const double crosspoint_s = lundeby_.crosspoint / fs_;
  tail_energy_ = std::pow(10.0, (lundeby_.intercept_db + lundeby_.slope_db_per_s * crosspoint_s) / 10.0) /
                 decayRatePerS();
}

double EnergyDecay::decayRatePerS() const {
  return -lundeby_.slope_db_per_s * std::log(10.0) / 10.0;
}

double EnergyDecay::tailEnergy() const { return tail_energy_; }

double EnergyDecay::energyAfter(double t_s) const {
  if (!valid()) return 0.0;
  const double crosspoint_s = lundeby_.crosspoint / fs_;
  if (t_s >= crosspoint_s) return tailEnergy() * std::exp(-decayRatePerS() * (t_s - crosspoint_s));
  const auto n = static_cast<std::size_t>(std::max(0.0, std::round(t_s * fs_)));
  // Subtraction can leave the running sum slightly negative just before the crosspoint,
  // where noise fluctuations dominate; energy remaining never falls below the tail.
  return std::max(0.0, backward_[std::min(n, backward_.size() - 1)]) + tailEnergy();
}

double EnergyDecay::levelDb(double t_s) const {
  const double total = energyAfter(0.0);
  const double remaining = energyAfter(t_s);
  if (total <= 0.0 || remaining <= 0.0) return -std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(remaining / total);
}

double EnergyDecay::centreTimeS() const {
  if (!valid()) return 0.0;
  // Past the crosspoint: integral of t * P_c exp(-delta (t - t_c)) = E_tail (t_c + 1/delta).
  const double crosspoint_s = lundeby_.crosspoint / fs_;
  const double moment = first_moment_ + tailEnergy() * (crosspoint_s + 1.0 / decayRatePerS());
  return moment / energyAfter(0.0);
}

double EnergyDecay::decayTimeS(double start_db, double end_db) const {
  const DecayLine line = fitLine(start_db, end_db);
  return line.valid ? -60.0 / line.slope_db_per_s : -1.0;
}

DecayLine EnergyDecay::fitLine(double start_db, double end_db) const {
  DecayLine line;
  if (!valid()) return line;
  const double total = energyAfter(0.0);
  if (!(total > 0.0)) return line;
  const double start_energy = total * std::pow(10.0, start_db / 10.0);
  const double end_energy = total * std::pow(10.0, end_db / 10.0);
  // Walk the curve sample by sample (past the crosspoint it is the analytic line, so the
  // walk always ends) and fit a line to the samples between the two levels. The level is
  // taken with the natural logarithm: glibc's log10 costs twice as much, and the fit reads
  // one per sample.
  const double to_db = 10.0 / std::log(10.0);
  double s_t = 0, s_l = 0, s_tt = 0, s_tl = 0;
  std::size_t count = 0;
  const double max_s = lundeby_.crosspoint / fs_ + (end_db - 10.0) / lundeby_.slope_db_per_s;
  for (std::size_t n = 0;; ++n) {
    const double t = n / fs_;
    if (t > max_s) break;
    const double remaining = energyAfter(t);
    if (remaining > start_energy) continue;
    if (remaining < end_energy) break;
    const double level = to_db * std::log(remaining / total);
    s_t += t; s_l += level; s_tt += t * t; s_tl += t * level;
    ++count;
  }
  if (count < 2) return line;
  const double n = static_cast<double>(count);
  const double denominator = n * s_tt - s_t * s_t;
  if (!(denominator > 0.0)) return line;
  line.slope_db_per_s = (n * s_tl - s_t * s_l) / denominator;
  line.intercept_db = (s_l - line.slope_db_per_s * s_t) / n;
  line.valid = line.slope_db_per_s < 0.0;
  return line;
}

}  // namespace room_reverb::core
