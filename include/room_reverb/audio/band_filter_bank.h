#pragma once
// Zero-phase, power-complementary fractional-octave filter bank, applied in the frequency
// domain.
//
// Why not IEC 61260 IIR filters: their skirts overlap, so band energies do not add up to
// the broadband energy, and their phase delays and ringing bias decay times in the low
// bands (Jacobsen's B*T limit). Here adjacent bands cross over with cos/sin amplitude
// responses on a log-frequency axis, so |H_k|^2 sums to one inside the bank's range
// (energy is kept exactly, by Parseval), each band is -3 dB at its edges as IEC 61260
// asks, and is exactly zero one band away. The filters are zero-phase: no group delay
// shifts a band's decay against another's.
#include <cstddef>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {

class BandFilterBank {
 public:
  // `crossover_fraction`: width of each crossover on the log2 axis, centred on the band
  // edge, as a fraction of the band width (in (0, 1]). The default, one half, leaves the
  // central half of each band flat.
  BandFilterBank(std::vector<FrequencyBand> bands, double sample_rate_hz,
                 double crossover_fraction = 0.5);

  const std::vector<FrequencyBand>& bands() const { return bands_; }
  double sampleRateHz() const { return sample_rate_hz_; }
  // A band is usable only if its centre lies below the Nyquist frequency.
  bool bandBelowNyquist(std::size_t band) const;

  // Amplitude response of band `band` at `frequency_hz` (real, non-negative: zero phase).
  double gain(std::size_t band, double frequency_hz) const;

  // Splits `signal` into one signal per band, each as long as the input. The signal is
  // zero-padded to twice its length so the filters' two-sided responses do not wrap around.
  std::vector<std::vector<float>> split(const std::vector<float>& signal) const;

 private:
  std::vector<FrequencyBand> bands_;
  double sample_rate_hz_;
  double crossover_octaves_;
};

}  // namespace room_reverb::core
