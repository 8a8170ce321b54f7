// LPC by Levinson-Durbin and its second-order-section form (RSAO, Remaggi et al. 2.1),
// against processes and filters whose coefficients are known.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <complex>
#include <random>

#include "room_reverb/common/error.h"
#include "room_reverb/rsao/lpc.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;

// x[n] = e[n] - sum a[i] x[n-i], e unit-variance white noise: an AR process with A(z) = a.
std::vector<double> autoregressive(const std::vector<double>& a, std::size_t length, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> e(length);
  for (auto& v : e) v = normal(rng);
  return filterAllPole(a, 1.0, e);
}

// A(z) of poles at radius r and angles +-theta, for each (r, theta).
std::vector<double> polynomialFromPolePairs(const std::vector<std::pair<double, double>>& pairs) {
  std::vector<double> a{1.0};
  for (const auto& [r, theta] : pairs) {
    const std::vector<double> quad{1.0, -2.0 * r * std::cos(theta), r * r};
    std::vector<double> product(a.size() + 2, 0.0);
    for (std::size_t i = 0; i < a.size(); ++i)
      for (std::size_t j = 0; j < 3; ++j) product[i + j] += a[i] * quad[j];
    a = product;
  }
  return a;
}

std::vector<double> impulse(std::size_t length) {
  std::vector<double> x(length, 0.0);
  x[0] = 1.0;
  return x;
}

double maxRelativeDifference(const std::vector<double>& x, const std::vector<double>& reference) {
  double diff = 0.0, peak = 0.0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    diff = std::max(diff, std::abs(x[n] - reference[n]));
    peak = std::max(peak, std::abs(reference[n]));
  }
  return diff / peak;
}

}  // namespace

TEST(Lpc, RecoversAnAr2Process) {
  // Poles at 0.9 e^{+-j pi/5}: a = [1, -1.4562, 0.81].
  const auto a = polynomialFromPolePairs({{0.9, kPi / 5}});
  const std::size_t n = 200000;
  const LpcModel model = fitLpc(autoregressive(a, n, 7), 2);
  ASSERT_EQ(model.a.size(), 3u);
  EXPECT_DOUBLE_EQ(model.a[0], 1.0);
  EXPECT_NEAR(model.a[1], -1.4562, 0.01);
  EXPECT_NEAR(model.a[2], 0.81, 0.01);
  // The residual energy is that of the driving noise: n samples of unit variance.
  EXPECT_NEAR(model.gain * model.gain / n, 1.0, 0.02);
}

TEST(Lpc, RecoversAnAr4ProcessAndHigherOrdersAddNothing) {
  const auto a = polynomialFromPolePairs({{0.95, 0.3}, {0.8, 1.9}});
  ASSERT_EQ(a.size(), 5u);
  const auto x = autoregressive(a, 200000, 11);
  const LpcModel four = fitLpc(x, 4);
  for (std::size_t i = 1; i <= 4; ++i) EXPECT_NEAR(four.a[i], a[i], 0.015) << "a[" << i << "]";
  const LpcModel nine = fitLpc(x, 9);
  for (std::size_t i = 1; i <= 4; ++i) EXPECT_NEAR(nine.a[i], a[i], 0.02) << "a[" << i << "]";
  for (std::size_t i = 5; i <= 9; ++i) EXPECT_NEAR(nine.a[i], 0.0, 0.02) << "a[" << i << "]";
}

TEST(Lpc, LevinsonDurbinSolvesTheToeplitzNormalEquations) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x(96);
  for (std::size_t n = 0; n < x.size(); ++n) x[n] = normal(rng) * (0.54 - 0.46 * std::cos(2 * kPi * n / 95.0));
  const int p = 9;
  const auto r = autocorrelation(x, p);
  Eigen::MatrixXd toeplitz(p, p);
  Eigen::VectorXd rhs(p);
  for (int i = 0; i < p; ++i) {
    rhs(i) = -r[static_cast<std::size_t>(i + 1)];
    for (int j = 0; j < p; ++j) toeplitz(i, j) = r[static_cast<std::size_t>(std::abs(i - j))];
  }
  const Eigen::VectorXd solution = toeplitz.ldlt().solve(rhs);
  const LpcModel model = levinsonDurbin(r, p);
  for (int i = 0; i < p; ++i) EXPECT_NEAR(model.a[static_cast<std::size_t>(i + 1)], solution(i), 1e-9);
  // Minimum phase: every reflection coefficient inside the unit circle.
  for (double k : model.reflection_coefficients) EXPECT_LT(std::abs(k), 1.0);
}

TEST(Lpc, GainMatchesTheSegmentEnergy) {
  // The autocorrelation method matches lags 0..p, so gain / A(z) has the segment's energy.
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x(120);
  for (auto& v : x) v = normal(rng);
  const LpcModel model = fitLpc(x, 9);
  const auto h = filterAllPole(model.a, model.gain, impulse(20000));
  double energy_h = 0.0, energy_x = 0.0;
  for (double v : h) energy_h += v * v;
  for (double v : x) energy_x += v * v;
  EXPECT_NEAR(energy_h / energy_x, 1.0, 1e-6);
}

TEST(Lpc, SectionsReproduceTheDirectFormFilter) {
  // Three cases: even order with complex poles only, odd order (one real pole left over),
  // and an order-9 fit of a short noisy segment (what the estimator produces).
  std::vector<std::pair<std::vector<double>, double>> filters;
  filters.push_back({polynomialFromPolePairs({{0.97, 0.2}, {0.9, 1.1}, {0.85, 2.5}}), 0.3});
  {
    auto a = polynomialFromPolePairs({{0.93, 0.7}, {0.6, 2.9}});
    // Times (1 - 0.75 z^-1): a real pole, order 5.
    std::vector<double> odd(a.size() + 1, 0.0);
    for (std::size_t i = 0; i < a.size(); ++i) {
      odd[i] += a[i];
      odd[i + 1] -= 0.75 * a[i];
    }
    filters.push_back({odd, 1.7});
  }
  {
    std::mt19937 rng(9);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::vector<double> x(96);
    for (std::size_t n = 0; n < x.size(); ++n) x[n] = normal(rng) + (n > 0 ? 0.9 * x[n - 1] : 0.0);
    const LpcModel m = fitLpc(x, 9);
    filters.push_back({m.a, m.gain});
  }
  for (const auto& [a, gain] : filters) {
    const std::size_t order = a.size() - 1;
    const auto sections = allPoleToSections(a, gain);
    EXPECT_EQ(sections.size(), (order + 1) / 2);
    std::size_t first_order = 0;
    for (const auto& s : sections) {
      EXPECT_LT(std::abs(s.a2), 1.0);  // poles inside the unit circle
      if (s.a2 == 0.0 && s.b2 == 0.0 && s.a1 != 0.0) ++first_order;
    }
    EXPECT_EQ(first_order, order % 2) << "order " << order;
    const auto reference = filterAllPole(a, gain, impulse(4000));
    EXPECT_LT(maxRelativeDifference(filterSections(sections, impulse(4000)), reference), 1e-6) << "order " << order;
  }
}

TEST(Lpc, SilenceGivesAFlatModelWithZeroGain) {
  const LpcModel model = fitLpc(std::vector<double>(50, 0.0), 9);
  ASSERT_EQ(model.a.size(), 10u);
  EXPECT_EQ(model.a[0], 1.0);
  for (std::size_t i = 1; i < model.a.size(); ++i) EXPECT_EQ(model.a[i], 0.0);
  EXPECT_EQ(model.gain, 0.0);
  const auto y = filterSections(allPoleToSections(model.a, model.gain), impulse(10));
  for (double v : y) EXPECT_EQ(v, 0.0);
}

TEST(Lpc, AnExponentialIsAFirstOrderProcess) {
  std::vector<double> x(200);
  for (std::size_t n = 0; n < x.size(); ++n) x[n] = std::pow(0.5, static_cast<double>(n));
  const LpcModel model = fitLpc(x, 9);
  EXPECT_NEAR(model.a[1], -0.5, 1e-9);
  for (std::size_t i = 2; i < model.a.size(); ++i) EXPECT_NEAR(model.a[i], 0.0, 1e-9);
}

TEST(Lpc, AFullyPredictedSequenceStopsTheRecursion) {
  // r = [1, 1, 1, 1] (a constant seen forever) is predicted exactly by x[n] = x[n-1]:
  // k1 = -1 leaves no error, and a further step would divide 0 by 0.
  const LpcModel model = levinsonDurbin({1.0, 1.0, 1.0, 1.0}, 3);
  ASSERT_EQ(model.a.size(), 4u);
  EXPECT_DOUBLE_EQ(model.a[1], -1.0);
  EXPECT_EQ(model.a[2], 0.0);
  EXPECT_EQ(model.a[3], 0.0);
  EXPECT_EQ(model.gain, 0.0);
}

TEST(Lpc, BadInputIsAClearError) {
  expectInputError([] { levinsonDurbin({1.0, 0.5}, 0); }, {"order", "at least 1"});
  expectInputError([] { levinsonDurbin({1.0, 0.5}, 3); }, {"order 3", "4 autocorrelation lags"});
  expectInputError([] { levinsonDurbin({1.0, std::nan("")}, 1); }, {"NaN"});
  expectInputError([] { allPoleToSections({2.0, 0.5}, 1.0); }, {"a[0] must be 1"});
  expectInputError([] { filterAllPole({}, 1.0, {1.0}); }, {"a[0] must be 1"});
}

// The fit held below a cutoff (early_reflections.h: a 2 ms window resolves nothing below
// about 500 Hz): the autocorrelation of a spectrum that is the segment's above the cutoff
// and flat at its value there below it, against that definition integrated directly.
TEST(Lpc, TheSpectrumHeldBelowACutoffIsTheDefinitionsAutocorrelation) {
  // A Hamming-windowed 96-sample segment: a pulse, its neighbour 0.4 ms later and a slow
  // swell under them.
  std::vector<double> x(96, 0.0);
  x[48] = 1.0;
  x[67] = -0.6;
  for (std::size_t n = 0; n < x.size(); ++n) {
    x[n] += 0.2 * std::sin(2.0 * kPi * 150.0 * static_cast<double>(n) / 48000.0 + 0.4);
    x[n] *= 0.54 - 0.46 * std::cos(2.0 * kPi * static_cast<double>(n) / 95.0);
  }
  const std::vector<double> r = autocorrelation(x, 9);
  EXPECT_EQ(autocorrelationFlatBelow(x, 9, 0.0), r);
  const auto power = [&](double w) {
    std::complex<double> sum = 0.0;
    for (std::size_t n = 0; n < x.size(); ++n) sum += x[n] * std::polar(1.0, -w * static_cast<double>(n));
    return std::norm(sum);
  };
  for (const double cutoff_hz : {300.0, 500.0, 1000.0}) {
    const double cutoff = 2.0 * kPi * cutoff_hz / 48000.0;
    // r[k] = (1/pi) int_0^pi P(w) cos(k w) dw, by the midpoint rule on a fine grid.
    constexpr int kSteps = 20000;
    std::vector<double> expected(10, 0.0);
    for (int i = 0; i < kSteps; ++i) {
      const double w = (i + 0.5) * kPi / kSteps, p = w < cutoff ? power(cutoff) : power(w);
      for (std::size_t k = 0; k < expected.size(); ++k) expected[k] += p * std::cos(static_cast<double>(k) * w) / kSteps;
    }
    const double scale = r[0] / expected[0];  // the segment's energy kept
    for (double& v : expected) v *= scale;
    const std::vector<double> held = autocorrelationFlatBelow(x, 9, cutoff);
    EXPECT_DOUBLE_EQ(held[0], r[0]) << cutoff_hz;
    for (std::size_t k = 0; k < held.size(); ++k) EXPECT_NEAR(held[k], expected[k], 1e-3 * r[0]) << cutoff_hz << " Hz, lag " << k;
    // It changes the low band only: the shapes differ, the fits stay stable.
    double change = 0.0;
    for (std::size_t k = 1; k < held.size(); ++k) change = std::max(change, std::abs(held[k] - r[k]));
    EXPECT_GT(change, 1e-3 * r[0]) << cutoff_hz;
    for (double k : levinsonDurbin(held, 9).reflection_coefficients) EXPECT_LT(std::abs(k), 1.0) << cutoff_hz;
  }
}

TEST(Lpc, TheHeldSpectrumStaysAValidAutocorrelationOverAWideRange) {
  // A segment whose energy sits almost all below the cutoff (a low hum under a faint
  // click): the held spectrum is still non-negative, so the recursion stays minimum phase
  // and the sections stable.
  std::vector<double> x(96);
  for (std::size_t n = 0; n < x.size(); ++n) {
    x[n] = std::sin(2.0 * kPi * 60.0 * static_cast<double>(n) / 48000.0) * (0.54 - 0.46 * std::cos(2.0 * kPi * static_cast<double>(n) / 95.0));
  }
  x[40] += 1e-4;
  for (double cutoff_hz : {200.0, 500.0, 1000.0}) {
    const LpcModel m = levinsonDurbin(autocorrelationFlatBelow(x, 9, 2.0 * kPi * cutoff_hz / 48000.0), 9);
    for (double k : m.reflection_coefficients) EXPECT_LT(std::abs(k), 1.0) << cutoff_hz;
    for (const BiquadSection& s : allPoleToSections(m.a, m.gain)) {
      EXPECT_LT(std::abs(s.a2), 1.0) << cutoff_hz;
      EXPECT_LT(std::abs(s.a1), 1.0 + s.a2) << cutoff_hz;
    }
  }
}
