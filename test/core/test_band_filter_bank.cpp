#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "room_reverb/audio/band_filter_bank.h"
#include "synthetic_rir.h"

using namespace room_reverb::core;
using room_reverb::test::energy;

namespace {

double sumOfBandEnergies(const BandFilterBank& bank, const std::vector<float>& x) {
  double sum = 0.0;
  for (const auto& band : bank.split(x)) sum += energy(band);
  return sum;
}

}  // namespace

TEST(FrequencyBands, StandardSets) {
  const auto octaves = standardBands(BandResolution::kOctave);
  ASSERT_EQ(octaves.size(), 9u);
  EXPECT_EQ(octaves.front().nominal_hz, 63);
  EXPECT_EQ(octaves.back().nominal_hz, 16000);
  EXPECT_DOUBLE_EQ(octaves[4].center_hz, 1000.0);
  EXPECT_NEAR(octaves[4].upper_hz, 1000.0 * std::sqrt(2.0), 1e-9);
  const auto thirds = standardBands(BandResolution::kThirdOctave);
  ASSERT_EQ(thirds.size(), 31u);
  EXPECT_EQ(thirds.front().nominal_hz, 20);
  EXPECT_EQ(thirds.back().nominal_hz, 20000);
  EXPECT_DOUBLE_EQ(thirds[17].center_hz, 1000.0);
  // Adjacent bands share their edges.
  for (std::size_t b = 1; b < thirds.size(); ++b) EXPECT_NEAR(thirds[b].lower_hz, thirds[b - 1].upper_hz, 1e-9);
}

TEST(BandFilterBank, ResponsesArePowerComplementaryInsideTheRange) {
  for (auto resolution : {BandResolution::kOctave, BandResolution::kThirdOctave}) {
    const BandFilterBank bank(standardBands(resolution), 48000.0);
    const auto& bands = bank.bands();
    for (double f = bands.front().center_hz; f <= bands.back().center_hz; f *= 1.01) {
      double power = 0.0;
      for (std::size_t b = 0; b < bands.size(); ++b) power += bank.gain(b, f) * bank.gain(b, f);
      ASSERT_NEAR(power, 1.0, 1e-9) << f;
    }
    for (std::size_t b = 0; b < bands.size(); ++b) {
      EXPECT_NEAR(bank.gain(b, bands[b].center_hz), 1.0, 1e-12);
      EXPECT_NEAR(20 * std::log10(bank.gain(b, bands[b].upper_hz)), -3.01, 0.01);  // IEC: -3 dB at the edges
      if (b + 1 < bands.size()) {
        EXPECT_LT(bank.gain(b, bands[b + 1].center_hz), 1e-12);
      }
    }
  }
}

TEST(BandFilterBank, BandEnergiesSumToBroadbandWithinHalfADecibel) {
  // An impulse (flat spectrum) and white noise, octave and third-octave, at 48 kHz and
  // at 44.1 kHz where the top band reaches past Nyquist.
  for (double fs : {48000.0, 44100.0}) {
    for (auto resolution : {BandResolution::kOctave, BandResolution::kThirdOctave}) {
      const BandFilterBank bank(standardBands(resolution), fs);
      std::vector<float> impulse(static_cast<std::size_t>(fs), 0.0f);
      impulse[impulse.size() / 2] = 1.0f;
      const double ratio_impulse = sumOfBandEnergies(bank, impulse) / energy(impulse);
      EXPECT_LT(std::abs(10 * std::log10(ratio_impulse)), 0.5) << fs << " " << toString(resolution);
      const std::vector<float> noise = room_reverb::test::whiteNoise(static_cast<std::size_t>(fs), 9);
      const double ratio_noise = sumOfBandEnergies(bank, noise) / energy(noise);
      EXPECT_LT(std::abs(10 * std::log10(ratio_noise)), 0.5) << fs << " " << toString(resolution);
    }
  }
}

TEST(BandFilterBank, SineLandsInItsBandOnly) {
  const BandFilterBank bank(standardBands(BandResolution::kOctave), 48000.0);
  std::vector<float> sine(48000);
  for (std::size_t n = 0; n < sine.size(); ++n) sine[n] = static_cast<float>(std::sin(2 * M_PI * 1000.0 * n / 48000.0));
  const auto bands = bank.split(sine);
  const double total = energy(sine);
  EXPECT_NEAR(energy(bands[4]) / total, 1.0, 0.01);
  for (std::size_t b = 0; b < bands.size(); ++b) {
    if (b != 4) {
      EXPECT_LT(energy(bands[b]) / total, 1e-4) << b;
    }
  }
}

TEST(BandFilterBank, BandsAboveNyquistAreSilent) {
  const BandFilterBank bank(standardBands(BandResolution::kOctave), 22050.0);
  EXPECT_FALSE(bank.bandBelowNyquist(8));  // 16 kHz at 22.05 kHz sampling
  const auto bands = bank.split(room_reverb::test::whiteNoise(2205, 2));
  EXPECT_EQ(energy(bands[8]), 0.0);
}

TEST(BandFilterBank, MixedWidthsStayComplementaryInBothSenses) {
  // Octaves up to 500 Hz, then thirds: at the shared 707 Hz edge the narrower band sets
  // the crossover. A power bank's |H|^2 and an amplitude bank's H must both sum to one
  // everywhere between the first band's centre and the last band's centre.
  std::vector<FrequencyBand> bands;
  for (const FrequencyBand& b : standardBands(BandResolution::kOctave)) {
    if (b.nominal_hz <= 500.0) bands.push_back(b);
  }
  const double edge = bands.back().upper_hz;
  for (const FrequencyBand& b : standardBands(BandResolution::kThirdOctave)) {
    if (b.center_hz > edge && b.center_hz < 17000.0) bands.push_back(b);
  }
  const BandFilterBank power(bands, 48000.0, 0.5, Complementarity::kPower);
  const BandFilterBank amplitude(bands, 48000.0, 0.5, Complementarity::kAmplitude);
  double worst_power = 0.0, worst_amplitude = 0.0;
  for (double f = bands.front().center_hz; f < bands.back().center_hz; f *= 1.003) {
    double sum_power = 0.0, sum_amplitude = 0.0;
    for (std::size_t b = 0; b < bands.size(); ++b) {
      sum_power += power.gain(b, f) * power.gain(b, f);
      sum_amplitude += amplitude.gain(b, f);
    }
    worst_power = std::max(worst_power, std::abs(sum_power - 1.0));
    worst_amplitude = std::max(worst_amplitude, std::abs(sum_amplitude - 1.0));
  }
  EXPECT_LT(worst_power, 1e-9);
  EXPECT_LT(worst_amplitude, 1e-9);
  // The amplitude bank rebuilds a signal from its bands.
  const std::vector<float> noise = room_reverb::test::whiteNoise(4800, 3);
  const auto parts = amplitude.split(noise);
  std::vector<float> rebuilt(noise.size(), 0.0f);
  for (const auto& part : parts) {
    for (std::size_t n = 0; n < noise.size(); ++n) rebuilt[n] += part[n];
  }
  // Compare the 1-10 kHz content only (the bank covers 63 Hz .. 16 kHz).
  const BandFilterBank probe({FrequencyBand{3000.0, 3000.0, 1000.0, 9000.0}}, 48000.0);
  const double error = energy(probe.split(noise)[0]) - energy(probe.split(rebuilt)[0]);
  EXPECT_LT(std::abs(error) / energy(probe.split(noise)[0]), 1e-3);
}

// A band at a reduced rate is the same band signal, sampled less often: its samples are
// the full-rate band's at their times (to within the error of linear interpolation between
// the full-rate samples, (2 pi f / fs)^2 / 8 of the peak at the support's top f), and its energy
// integral is the full-rate one's. A band whose support reaches the input's Nyquist
// frequency keeps the input's rate and samples.
TEST(BandFilterBank, DecimatedBandsAreTheBandsSampledLessOften) {
  constexpr double kFs = 48000.0;
  std::mt19937 rng(3);
  std::normal_distribution<float> normal;
  std::vector<float> x(24000);
  for (std::size_t n = 0; n < x.size(); ++n) x[n] = normal(rng) * static_cast<float>(std::exp(-3.0 * n / kFs));
  const BandFilterBank bank(standardBands(BandResolution::kOctave), kFs);
  const BandFilterBank::PaddedSpectrum spectrum = bank.analyse(x);
  for (std::size_t b = 0; b < bank.bands().size(); ++b) {
    const std::vector<float> full = bank.extract(spectrum, b);
    const BandFilterBank::DecimatedBand low = bank.extractDecimated(spectrum, b);
    // The top of the band's support, from its gain: the highest frequency it passes (1 Hz
    // steps; the gain is zero beyond it up to rounding).
    double support_top_hz = 0.5 * kFs;
    while (support_top_hz > 0.0 && bank.gain(b, support_top_hz) < 1e-9) support_top_hz -= 1.0;
    EXPECT_GE(low.sample_rate_hz, std::min(kFs, 7.9 * support_top_hz)) << "band " << b;
    if (bank.bands()[b].center_hz <= 250.0) {
      EXPECT_LT(low.sample_rate_hz, kFs / 10.0) << "band " << b;
    }
    double peak = 0.0, worst = 0.0, full_energy = 0.0, low_energy = 0.0;
    for (float v : full) {
      peak = std::max(peak, std::abs(static_cast<double>(v)));
      full_energy += static_cast<double>(v) * v / kFs;
    }
    for (std::size_t m = 0; m < low.signal.size(); ++m) {
      low_energy += static_cast<double>(low.signal[m]) * low.signal[m] / low.sample_rate_hz;
      const double at = static_cast<double>(m) * kFs / low.sample_rate_hz;
      const auto i = static_cast<std::size_t>(at);
      if (i + 1 >= full.size()) break;
      const double f = at - static_cast<double>(i);
      worst = std::max(worst, std::abs(low.signal[m] - ((1.0 - f) * full[i] + f * full[i + 1])));
    }
    const double interpolation = std::pow(2.0 * M_PI * support_top_hz / kFs, 2) / 8.0;
    EXPECT_LT(worst, (interpolation + 1e-4) * peak) << "band " << b << " at " << low.sample_rate_hz << " Hz";
    EXPECT_NEAR(low_energy, full_energy, 1e-3 * full_energy) << "band " << b;
    if (low.sample_rate_hz == kFs) {
      EXPECT_EQ(low.signal, full);
    }
  }
  EXPECT_THROW(bank.extractDecimated(spectrum, 0, 1.5), std::invalid_argument);
}
