#pragma once
// Schroeder's backward-integrated energy decay curve (Schroeder 1965; ISO 3382-1 5.3.3),
// truncated where the decay meets the noise and compensated for the energy lost past that
// point (Lundeby et al. 1995: the late decay line extrapolated to infinity).
#include <cstddef>
#include <vector>

#include "room_reverb/metrics/lundeby.h"

namespace room_reverb::core {

// Least-squares line level(t) = intercept_db + slope_db_per_s * t through a decay curve in
// dB re its total energy, t in seconds from the onset.
struct DecayLine {
  bool valid = false;  // at least two points and a falling slope
  double slope_db_per_s = 0.0;
  double intercept_db = 0.0;
};

class EnergyDecay {
 public:
  // `signal`: a (band-filtered) impulse response; analysis starts at `onset`.
  EnergyDecay(const std::vector<float>& signal, std::size_t onset, double sample_rate_hz);
  // From the response's energy per sample instead of its samples (squared samples, or a
  // band's energy envelope, BandFilterBank::extractEnergyEnvelope), from `onset` on.
  EnergyDecay(const std::vector<double>& energy, std::size_t onset, double sample_rate_hz);

  const LundebyResult& lundeby() const { return lundeby_; }
  bool valid() const { return lundeby_.valid; }
  double sampleRateHz() const { return fs_; }
  // Peak level minus noise level, the range ISO 3382-1 5.3.3 judges T20/T30 by.
  double decayRangeDb() const { return lundeby_.peak_db - lundeby_.noise_db; }

  // Energy remaining after time t (seconds from the onset), compensated: the integral of
  // the squared response from t to infinity. energyAfter(0) is the total energy.
  double energyAfter(double t_s) const;
  // The same in dB re the total energy (0 dB at the onset, falling).
  double levelDb(double t_s) const;
  // Energy-weighted mean arrival time (centre time Ts), seconds from the onset.
  double centreTimeS() const;

  // Reverberation time from a least-squares line through the curve between `start_db`
  // and `end_db` (e.g. -5 and -25 for T20), scaled to 60 dB. Negative if the curve never
  // reaches `end_db`.
  double decayTimeS(double start_db, double end_db) const;
  // The line itself, through every sample of the curve from `start_db` down to `end_db`.
  DecayLine fitLine(double start_db, double end_db) const;

 private:
  void integrate(const std::vector<double>& energy);  // Lundeby, then the backward integral
  double tailEnergy() const;    // compensation: energy past the crosspoint
  double decayRatePerS() const; // delta of the energy envelope exp(-delta t)

  double fs_;
  LundebyResult lundeby_;
  std::vector<double> backward_;  // backward_[n]: sum of energy from n to the crosspoint, / fs
  double first_moment_ = 0.0;     // sum of t * energy up to the crosspoint, / fs
  double tail_energy_ = 0.0;      // tailEnergy(), computed once: energyAfter() is read per sample
};

}  // namespace room_reverb::core
