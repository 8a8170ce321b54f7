#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/audio/fft.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/late_reverb.h"
#include "room_reverb/rsao/analysis_window.h"
#include "room_reverb/rsao/rsao_resynthesis.h"
#include "synthetic_rsao.h"

using namespace room_reverb::core;

namespace {

constexpr double kFs = 48000.0;

// A room-like late part: decay and level falling gently with frequency, as air and porous
// absorption make them; the onset ramp from 10 ms, the mixing time at 60 ms.
const std::vector<double> kT60 = {1.8, 1.6, 1.4, 1.2, 1.0, 0.9, 0.8, 0.6, 0.45};
const std::vector<double> kLevel = {0.02, 0.03, 0.04, 0.05, 0.05, 0.04, 0.03, 0.02, 0.014};

Rsao roomLikeRsao() {
  Rsao rsao = room_reverb::test::roomLikeLateRsao(2.0);
  // Direct sound and three reflections, all before the mixing time.
  auto add = [&](double toa, double level, double az_deg, double el_deg) {
    EarlyReflection r;
    r.time_of_arrival_s = toa;
    r.level = level;
    r.azimuth_rad = az_deg * M_PI / 180.0;
    r.elevation_rad = el_deg * M_PI / 180.0;
    rsao.reflections.push_back(r);
  };
  add(0.0040, 0.30, 0.0, 0.0);
  add(0.0112, 0.15, 60.0, -20.0);
  add(0.0187, 0.12, -120.0, 10.0);
  add(0.0251, 0.10, 170.0, 45.0);
  return rsao;
}

// Energy under the estimator's analysis window: Hamming, length d_s, centred on arrival_s.
double windowedEnergy(const std::vector<float>& x, double arrival_s, double d_s) {
  const SampleWindow window = hammingWindowAt(arrival_s * kFs, d_s * kFs, x.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < window.weights.size(); ++i) sum += std::pow(window.weights[i] * x[window.first + i], 2);
  return sum;
}

double energyBetween(const std::vector<float>& x, std::size_t first, std::size_t last) {
  double e = 0.0;
  for (std::size_t n = first; n < last && n < x.size(); ++n) e += static_cast<double>(x[n]) * x[n];
  return e;
}

Rsao singleReflection(double toa_s, double level, double az, double el) {
  Rsao rsao;
  rsao.duration_s = 0.1;
  EarlyReflection r;
  r.time_of_arrival_s = toa_s;
  r.level = level;
  r.azimuth_rad = az;
  r.elevation_rad = el;
  rsao.reflections.push_back(r);
  return rsao;
}

}  // namespace

TEST(RsaoResynthesis, LateReverbRoundTripsThroughTheEstimator) {
  const Rsao rsao = roomLikeRsao();
  const AudioBuffer ir = resynthesizeRsao(rsao);
  ASSERT_EQ(ir.channelCount(), 4u);
  EXPECT_EQ(ir.sample_rate_hz, 48000.0);
  EXPECT_EQ(ir.frameCount(), 96000u);
  const LateReverb late = estimateLateReverb(ir.channels[0], rsao.late.onset_s, rsao.late.mixing_time_s);
  for (std::size_t b = 0; b < 9; ++b) {
    const LateReverbBand& band = late.bands[b];
    EXPECT_TRUE(band.reliable) << band.center_hz << ": " << band.reason;
    // Measured over eight seeds: within 1.9 % and 0.3 dB.
    EXPECT_NEAR(band.t60_s, kT60[b], 0.05 * kT60[b]) << band.center_hz;
    EXPECT_NEAR(20.0 * std::log10(band.level / kLevel[b]), 0.0, 1.0) << band.center_hz;
  }
}

TEST(RsaoResynthesis, SameSeedSameSamplesOtherSeedOtherNoise) {
  Rsao rsao = roomLikeRsao();
  rsao.duration_s = 0.3;
  ResynthesisOptions options;
  options.seed = 7;
  const AudioBuffer a = resynthesizeRsao(rsao, options);
  const AudioBuffer b = resynthesizeRsao(rsao, options);
  EXPECT_EQ(a.channels, b.channels);
  options.seed = 8;
  const AudioBuffer c = resynthesizeRsao(rsao, options);
  EXPECT_NE(a.channels[0], c.channels[0]);
  // The early part does not depend on the seed.
  for (std::size_t n = 0; n < 480; ++n) EXPECT_EQ(a.channels[0][n], c.channels[0][n]) << n;
}

TEST(RsaoResynthesis, LateFieldIsDiffuseInSn3d) {
  Rsao rsao = roomLikeRsao();
  rsao.reflections.clear();
  const AudioBuffer ir = resynthesizeRsao(rsao);
  const std::size_t mix = 2880;
  const double w = energyBetween(ir.channels[0], mix, ir.frameCount());
  for (std::size_t c = 1; c < 4; ++c) {
    EXPECT_NEAR(energyBetween(ir.channels[c], mix, ir.frameCount()) / w, 1.0 / 3.0, 0.02) << c;
    // Independent noise: the normalised correlation with W is small. (It is one draw's
    // estimate over a few hundred independent cells of time and frequency, so not zero:
    // 0.05-0.12 here; a shared noise would give 1.)
    double cross = 0.0;
    for (std::size_t n = mix; n < ir.frameCount(); ++n) cross += static_cast<double>(ir.channels[0][n]) * ir.channels[c][n];
    EXPECT_LT(std::abs(cross) / std::sqrt(w * energyBetween(ir.channels[c], mix, ir.frameCount())), 0.25) << c;
  }
}

TEST(RsaoResynthesis, LateOnsetRampStartsAtTheOnsetAndRises) {
  Rsao rsao = roomLikeRsao();
  rsao.reflections.clear();
  rsao.duration_s = 0.3;
  for (OnsetRamp shape : {OnsetRamp::kLinear, OnsetRamp::kRaisedCosine}) {
    ResynthesisOptions options;
    options.onset_ramp = shape;
    const AudioBuffer ir = resynthesizeRsao(rsao, options);
    for (std::size_t c = 0; c < 4; ++c) {
      for (std::size_t n = 0; n < 480; ++n) ASSERT_EQ(ir.channels[c][n], 0.0f) << c << " " << n;
    }
    // Mean square over the ramp's quarters, against the model's integral of ramp^2.
    const std::size_t onset = 480, quarter = 600;
    const double full = energyBetween(ir.channels[0], 2880, 2880 + quarter);
    for (int q = 0; q < 4; ++q) {
      double expected = 0.0;
      for (int i = 0; i < 1000; ++i) {
        const double u = (q + (i + 0.5) / 1000.0) / 4.0;
        const double r = shape == OnsetRamp::kLinear ? u : 0.5 * (1.0 - std::cos(M_PI * u));
        expected += r * r / 1000.0;
      }
      const double measured = energyBetween(ir.channels[0], onset + q * quarter, onset + (q + 1) * quarter) / full;
      EXPECT_NEAR(measured, expected, 0.03 + 0.25 * expected) << "quarter " << q;
    }
  }
}

TEST(RsaoResynthesis, ReflectionHasItsLevelInTheWindowAndItsDirectionInTheChannels) {
  const double az = 2.1, el = -0.4, level = 0.25;
  for (bool filtered : {false, true}) {
    Rsao rsao = singleReflection(0.0123456, level, az, el);
    if (filtered) {
      BiquadSection lowpass;
      lowpass.b0 = 0.2; lowpass.b1 = 0.4; lowpass.b2 = 0.2; lowpass.a1 = -0.5; lowpass.a2 = 0.3;
      rsao.reflections[0].sos = {lowpass, lowpass};
    }
    ResynthesisOptions options;
    const AudioBuffer ir = resynthesizeRsao(rsao, options);
    const auto arrival = static_cast<std::size_t>(std::floor(0.0123456 * kFs));
    const std::size_t first = arrival - 15, last = arrival + 1 + static_cast<std::size_t>(0.005 * kFs);
    // W energy under the estimator's window (Hamming, D centred on the arrival) is level^2
    // (float rounding only): estimating the tap again gives its level back.
    EXPECT_NEAR(windowedEnergy(ir.channels[0], 0.0123456, options.analysis_window_s), level * level, 1e-6) << filtered;
    // Every channel is W times its SN3D harmonic.
    const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const std::vector<double> y = sn3dHarmonics(1, d);
    for (std::size_t c = 1; c < 4; ++c) {
      for (std::size_t n = first; n < last; ++n) {
        EXPECT_NEAR(ir.channels[c][n], y[c] * ir.channels[0][n], 1e-6) << c;
      }
    }
  }
}

TEST(RsaoResynthesis, ReflectionsArriveAtTheirFractionalTimes) {
  // Two taps a quarter-sample apart: the phase of their spectra's ratio is the delay.
  const double toa = 0.010, shift_samples = 0.25;
  const AudioBuffer a = resynthesizeRsao(singleReflection(toa, 1.0, 0.0, 0.0));
  const AudioBuffer b = resynthesizeRsao(singleReflection(toa + shift_samples / kFs, 1.0, 0.0, 0.0));
  RealFft fft(1024);
  std::vector<float> xa(1024, 0.0f), xb(1024, 0.0f);
  for (std::size_t n = 0; n < 1024; ++n) {
    xa[n] = a.channels[0][300 + n];
    xb[n] = b.channels[0][300 + n];
  }
  const auto sa = fft.forward(xa), sb = fft.forward(xb);
  for (std::size_t k = 20; k < 400; k += 20) {  // up to 18.75 kHz
    const double omega = 2.0 * M_PI * k / 1024.0;
    const double delay = -std::arg(std::complex<double>(sb[k]) / std::complex<double>(sa[k])) / omega;
    EXPECT_NEAR(delay, shift_samples, 0.01) << k * kFs / 1024 << " Hz";
  }
}

TEST(RsaoResynthesis, LpcReflectionIsShapedAndScaled) {
  Rsao rsao = singleReflection(0.005, 0.5, 0.0, 0.0);
  rsao.reflections[0].lpc = {1.0, -0.9};  // one pole at 0.9: a low-pass tilt
  rsao.reflections[0].lpc_gain = 0.3;
  const AudioBuffer ir = resynthesizeRsao(rsao);
  const std::size_t arrival = 240;
  EXPECT_NEAR(windowedEnergy(ir.channels[0], 0.005, ResynthesisOptions{}.analysis_window_s), 0.25, 1e-6);
  // After the kernel's main lobe, successive samples fall by the pole radius.
  EXPECT_NEAR(ir.channels[0][arrival + 40] / ir.channels[0][arrival + 39], 0.9, 0.01);
}

TEST(RsaoResynthesis, RefusesWhatItCannotRender) {
  Rsao rsao = roomLikeRsao();
  rsao.late.bands.pop_back();
  EXPECT_THROW(resynthesizeRsao(rsao), InputError);  // eight bands
  rsao = roomLikeRsao();
  rsao.late.bands[3].decay_constant_per_s = 0.0;
  EXPECT_THROW(resynthesizeRsao(rsao), InputError);
  rsao = roomLikeRsao();
  rsao.late.onset_s = 0.1;  // after the mixing time
  EXPECT_THROW(resynthesizeRsao(rsao), InputError);
  rsao = roomLikeRsao();
  rsao.reflections[1].sos = {BiquadSection{1.0, 0.0, 0.0, -2.1, 1.2}};  // poles outside the unit circle
  EXPECT_THROW(resynthesizeRsao(rsao), InputError);
  rsao = roomLikeRsao();
  rsao.reflections[2].lpc = {1.0, -1.5};
  EXPECT_THROW(resynthesizeRsao(rsao), InputError);
  rsao = roomLikeRsao();
  rsao.reflections[0].time_of_arrival_s = std::nan("");
  EXPECT_THROW(resynthesizeRsao(rsao), InputError);
  rsao = roomLikeRsao();
  rsao.duration_s = 100.0;
  EXPECT_THROW(resynthesizeRsao(rsao), InputError);
}
