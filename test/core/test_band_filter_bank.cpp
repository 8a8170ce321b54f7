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
// The envelope of a decaying noise holds the band's energy exactly (Parseval), at a rate
// set by the band's width and the floor asked for.
TEST(BandFilterBank, EnergyEnvelopeHoldsTheBandsEnergyAtAFractionOfTheRate) {
  constexpr double kFs = 48000.0;
  std::mt19937 rng(3);
  std::normal_distribution<float> normal;
  std::vector<float> x(24000);
  for (std::size_t n = 0; n < x.size(); ++n) x[n] = normal(rng) * static_cast<float>(std::exp(-3.0 * n / kFs));
  const BandFilterBank bank(standardBands(BandResolution::kOctave), kFs);
  const BandFilterBank::PaddedSpectrum spectrum = bank.analyse(x);
  for (std::size_t b = 0; b < bank.bands().size(); ++b) {
    const std::vector<float> full = bank.extract(spectrum, b);
    const BandFilterBank::BandEnergy envelope = bank.extractEnergyEnvelope(spectrum, b, 4000.0);
    // The support's width from the gain (1 Hz steps).
    double low_hz = 1.0, high_hz = 0.5 * kFs;
    while (low_hz < high_hz && bank.gain(b, low_hz) < 1e-9) low_hz += 1.0;
    while (high_hz > low_hz && bank.gain(b, high_hz) < 1e-9) high_hz -= 1.0;
    EXPECT_GE(envelope.sample_rate_hz, std::min(kFs, std::max(4000.0, 1.25 * (high_hz - low_hz)) - 2.0)) << "band " << b;
    // A rate set by the width, not the top: the 8 kHz octave at under half the input's.
    if (bank.bands()[b].center_hz <= 8000.0) {
      EXPECT_LT(envelope.sample_rate_hz, 0.5 * kFs) << "band " << b;
    }
    double full_energy = 0.0, envelope_energy = 0.0;
    for (float v : full) full_energy += static_cast<double>(v) * v / kFs;
    for (double e : envelope.energy) envelope_energy += e / envelope.sample_rate_hz;
    // Over the whole padded transform the two are equal; cut to the signal's length they
    // differ where the band rings across its start, a few periods: 0.25 % at 63 Hz.
    EXPECT_NEAR(envelope_energy, full_energy, (b == 0 ? 5e-3 : 1e-3) * full_energy) << "band " << b;
    // Over 20 ms blocks it follows the band's energy (a block's edges cut through the
    // band's ripple, so within a few per cent where the band is above its first octave).
    if (bank.bands()[b].center_hz < 500.0) continue;
    for (double t = 0.02; t + 0.02 < 0.4; t += 0.05) {
      double e_full = 0.0, e_envelope = 0.0;
      for (auto n = static_cast<std::size_t>(t * kFs); n < static_cast<std::size_t>((t + 0.02) * kFs); ++n) {
        e_full += static_cast<double>(full[n]) * full[n] / kFs;
      }
      const double r = envelope.sample_rate_hz;
      for (auto i = static_cast<std::size_t>(std::lround(t * r)); i < static_cast<std::size_t>(std::lround((t + 0.02) * r)); ++i) {
        e_envelope += envelope.energy[i] / r;
      }
      EXPECT_NEAR(e_envelope / e_full, 1.0, 0.15) << "band " << b << " at " << t << " s";
    }
  }
  EXPECT_THROW(bank.extractEnergyEnvelope(spectrum, 0, 4000.0, 0.9), std::invalid_argument);
  EXPECT_THROW(bank.extractEnergyEnvelope(spectrum, 0, -1.0), std::invalid_argument);
}

// A tone at a band's centre under a slow decay: the envelope is its squared amplitude
// over two, without the ripple at twice the tone's frequency that its squares carry.
TEST(BandFilterBank, EnergyEnvelopeOfADecayingToneIsItsSquaredAmplitudeOverTwo) {
  constexpr double kFs = 48000.0;
  const BandFilterBank bank(standardBands(BandResolution::kOctave), kFs);
  for (std::size_t b = 0; b < bank.bands().size(); ++b) {
    const double f = bank.bands()[b].center_hz;
    if (f >= 0.5 * kFs) continue;
    std::vector<float> x(48000);
    const auto amplitude = [](double t) { return std::exp(-t / 0.2); };
    for (std::size_t n = 0; n < x.size(); ++n) {
      const double t = static_cast<double>(n) / kFs;
      x[n] = static_cast<float>(amplitude(t) * std::cos(2.0 * M_PI * f * t));
    }
    const BandFilterBank::BandEnergy envelope = bank.extractEnergyEnvelope(bank.analyse(x), b, 1000.0);
    for (double t = 0.15; t < 0.6; t += 0.05) {
      const auto i = static_cast<std::size_t>(std::lround(t * envelope.sample_rate_hz));
      const double at = static_cast<double>(i) / envelope.sample_rate_hz;
      EXPECT_NEAR(envelope.energy[i] / (0.5 * std::pow(amplitude(at), 2)), 1.0, 0.01) << f << " Hz at " << t << " s";
    }
  }
}
