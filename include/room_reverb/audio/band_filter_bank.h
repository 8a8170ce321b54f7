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
#include <complex>
#include <cstddef>
#include <utility>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {

// How neighbouring bands share a crossover. kPower (cos/sin amplitudes): |H|^2 sums to one,
// so band energies of one signal add up to its energy (analysis). kAmplitude (cos^2/sin^2):
// H sums to one, so band signals of one signal add up to the signal again, and bands of
// one noise scaled by smoothly varying gains sum to noise with a smoothly varying spectrum
// (synthesis; with kPower the crossovers would carry up to twice the energy).
enum class Complementarity { kPower, kAmplitude };

class BandFilterBank {
 public:
  // `crossover_fraction`: width of each crossover on the log2 axis, centred on the band
  // edge, as a fraction of the band width (in (0, 1]). The default, one half, leaves the
  // central half of each band flat. Bands need not be of one width (octaves may be
  // followed by thirds); at a shared edge the narrower band sets the crossover.
  BandFilterBank(std::vector<FrequencyBand> bands, double sample_rate_hz,
                 double crossover_fraction = 0.5, Complementarity complementarity = Complementarity::kPower);

  const std::vector<FrequencyBand>& bands() const { return bands_; }
  double sampleRateHz() const { return sample_rate_hz_; }
  // A band is usable only if its centre lies below the Nyquist frequency.
  bool bandBelowNyquist(std::size_t band) const;

  // Amplitude response of band `band` at `frequency_hz` (real, non-negative: zero phase).
  double gain(std::size_t band, double frequency_hz) const;

  // Splits `signal` into one signal per band, each as long as the input. The signal is
  // zero-padded to twice its length so the filters' two-sided responses do not wrap around.
  std::vector<std::vector<float>> split(const std::vector<float>& signal) const;

  // The same split one band at a time, for when all bands of many signals would not fit in
  // memory together: analyse() once, then extract() each band that is needed.
  struct PaddedSpectrum {
    std::size_t signal_length = 0;
    std::size_t fft_size = 0;
    std::vector<std::complex<float>> bins;
  };
  PaddedSpectrum analyse(const std::vector<float>& signal) const;
  std::vector<float> extract(const PaddedSpectrum& spectrum, std::size_t band) const;

  // One band's energy envelope: energy[i] = |z(t_i)|^2 / 2, z the band signal's analytic
  // signal (extract() is its real part), sampled at t_i = i / sample_rate_hz. The band is
  // taken down to baseband and only its bins are transformed, so the rate follows the
  // band's width, not its top: at least `width_oversampling` (>= 1) times the width of its
  // support and at least `min_rate_hz`, or the input's rate where that is not lower. The
  // envelope is smooth (no ripple at twice the band's frequency), and by Parseval its sum
  // over the padded transform divided by the rate is exactly the band's energy, the sum of
  // extract()'s squares divided by the input's rate. Energy analyses (Schroeder curves,
  // band energies over a span) read the same from it at a fraction of the samples: a 1 s
  // response's 16 kHz octave in about 18 000 instead of 48 000.
  struct BandEnergy {
    std::vector<double> energy;
    double sample_rate_hz = 0.0;
  };
  BandEnergy extractEnergyEnvelope(const PaddedSpectrum& spectrum, std::size_t band, double min_rate_hz,
                                   double width_oversampling = 1.25) const;

 private:
  // The band's bins of `spectrum`, gains applied, into `out` (zeroed; as many bins as it
  // has room for), bin k at out[k - shift].
  void fillBandSpectrum(const PaddedSpectrum& spectrum, std::size_t band, std::vector<std::complex<float>>& out,
                        std::size_t shift = 0) const;
  // First and last bin of `spectrum` inside the band's support.
  std::pair<std::size_t, std::size_t> supportBins(const PaddedSpectrum& spectrum, std::size_t band) const;

  std::vector<FrequencyBand> bands_;
  double sample_rate_hz_;
  Complementarity complementarity_;
  std::vector<double> lower_crossover_octaves_;  // per band, on the log2 axis
  std::vector<double> upper_crossover_octaves_;
};

}  // namespace room_reverb::core
