#include "room_reverb/metrics/two_slope_decay.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace room_reverb::core {
namespace {

// The curve read at K evenly spaced times t_k = k dt, normalised to 1 at t = 0, kept as
// 1 / y_k: the relative error (A_1 f_1 + A_2 f_2 - y) / y is then A_1 g_1 + A_2 g_2 - 1
// with g_i = f_i / y, and each rate's f_i(t_k) = r_i^k a running product.
struct Samples {
  std::vector<double> inverse;
  std::vector<double> weight;  // the curve's local steepness: each dB of the fall counts alike
  double total_weight = 0.0;
  double dt = 0.0;
};

struct Amplitudes {
  double sse = 0.0;
  double fast = 0.0, slow = 0.0;
};

struct Sums {
  double s11 = 0, s12 = 0, s22 = 0, s1 = 0, s2 = 0;
};

Sums sumsFor(const Samples& s, double a1, double a2) {
  const double r1 = std::exp(-a1 * s.dt), r2 = std::exp(-a2 * s.dt);
  double f1 = 1.0, f2 = 1.0;
  Sums m;
  for (std::size_t k = 0; k < s.inverse.size(); ++k) {
    const double g1 = f1 * s.inverse[k], g2 = f2 * s.inverse[k], v = s.weight[k];
    m.s11 += v * g1 * g1;
    m.s12 += v * g1 * g2;
    m.s22 += v * g2 * g2;
    m.s1 += v * g1;
    m.s2 += v * g2;
    f1 *= r1;
    f2 *= r2;
  }
  return m;
}

// sum v (A g - 1)^2 at its minimum over A, from sum v = total_weight, sum v g = s and
// sum v g^2 = ss.
double oneTermSse(double total_weight, double s, double ss) { return ss > 0.0 ? total_weight - s * s / ss : total_weight; }

// Least squares in (A_1, A_2) >= 0 for the rates a1 > a2: the unconstrained 2 x 2 solution
// when both amplitudes come out non-negative, else the better one-term fit.
Amplitudes fitAmplitudes(const Samples& s, double a1, double a2) {
  const Sums m = sumsFor(s, a1, a2);
  const double total = s.total_weight;
  const double det = m.s11 * m.s22 - m.s12 * m.s12;
  Amplitudes a;
  if (det > 1e-12 * m.s11 * m.s22) {
    a.fast = (m.s22 * m.s1 - m.s12 * m.s2) / det;
    a.slow = (m.s11 * m.s2 - m.s12 * m.s1) / det;
    if (a.fast >= 0.0 && a.slow >= 0.0) {
      a.sse = total - 2.0 * (a.fast * m.s1 + a.slow * m.s2) + a.fast * a.fast * m.s11 +
              2.0 * a.fast * a.slow * m.s12 + a.slow * a.slow * m.s22;
      return a;
    }
  }
  const double sse_fast = oneTermSse(total, m.s1, m.s11), sse_slow = oneTermSse(total, m.s2, m.s22);
  if (sse_fast <= sse_slow) return {sse_fast, m.s11 > 0.0 ? m.s1 / m.s11 : 0.0, 0.0};
  return {sse_slow, 0.0, m.s22 > 0.0 ? m.s2 / m.s22 : 0.0};
}

Amplitudes fitOne(const Samples& s, double a) {
  const Sums m = sumsFor(s, a, a);
  return {oneTermSse(s.total_weight, m.s1, m.s11), m.s11 > 0.0 ? m.s1 / m.s11 : 0.0, 0.0};
}

double rmsErrorDb(const Samples& s, double a1, double e1, double a2, double e2) {
  double sum = 0.0;
  for (std::size_t k = 0; k < s.inverse.size(); ++k) {
    const double t = static_cast<double>(k) * s.dt;
    const double model = e1 * std::exp(-a1 * t) + e2 * std::exp(-a2 * t);
    const double error = model > 0.0 ? 10.0 * std::log10(model * s.inverse[k]) : 100.0;
    sum += s.weight[k] * error * error;
  }
  return std::sqrt(sum / s.total_weight);
}

// The best single rate: a log grid over a factor of 16 around `guess`, refined three times.
void fitSingle(const Samples& s, double guess, TwoSlopeFit& fit) {
  double best_u = std::log(guess), best = fitOne(s, guess).sse;
  double step = std::log(16.0) / 24.0;
  for (int k = -12; k <= 12; ++k) {
    const double u = std::log(guess) + k * step;
    const double sse = fitOne(s, std::exp(u)).sse;
    if (sse < best) best = sse, best_u = u;
  }
  for (int round = 0; round < 3; ++round) {
    step /= 4.0;
    const double centre = best_u;
    for (int k = -4; k <= 4; ++k) {
      const double u = centre + k * step;
      const double sse = fitOne(s, std::exp(u)).sse;
      if (sse < best) best = sse, best_u = u;
    }
  }
  fit.one_rate_per_s = std::exp(best_u);
  fit.one_energy = fitOne(s, fit.one_rate_per_s).fast;
}

// The best rate pair: the fast rate over [a, 12 a] and the slow one over [a / 6, a] on a
// 8 x 8 log grid (a the single rate), then Nelder-Mead on the two log rates from the
// grid's best point. The error valley is long and curved (a faster first slope with less
// energy fits almost as well), which nested grids follow poorly and a simplex follows.
void fitPair(const Samples& s, TwoSlopeFit& fit) {
  const double u0 = std::log(fit.one_rate_per_s);
  auto cost = [&](double u1, double u2) {
    return u1 > u2 ? fitAmplitudes(s, std::exp(u1), std::exp(u2)).sse : fitOne(s, std::exp(u1)).sse + 1.0;
  };
  double best_u1 = u0, best_u2 = u0, best = fitOne(s, fit.one_rate_per_s).sse;
  const double step1 = std::log(12.0) / 7.0, step2 = std::log(6.0) / 7.0;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      const double u1 = u0 + i * step1, u2 = u0 - j * step2;
      if (!(u1 > u2)) continue;
      const double c = cost(u1, u2);
      if (c < best) best = c, best_u1 = u1, best_u2 = u2;
    }
  }
  struct Vertex { double u1, u2, c; };
  Vertex v[3] = {{best_u1, best_u2, best}, {best_u1 + step1, best_u2, 0.0}, {best_u1, best_u2 - step2, 0.0}};
  for (int k = 1; k < 3; ++k) v[k].c = cost(v[k].u1, v[k].u2);
  // Stops when the simplex spans 1e-4 in the log rates: 0.01 % of a decay time.
  for (int iteration = 0; iteration < 150; ++iteration) {
    std::sort(v, v + 3, [](const Vertex& x, const Vertex& y) { return x.c < y.c; });
    if (std::abs(v[2].u1 - v[0].u1) + std::abs(v[2].u2 - v[0].u2) < 1e-4) break;
    const double m1 = 0.5 * (v[0].u1 + v[1].u1), m2 = 0.5 * (v[0].u2 + v[1].u2);
    auto towards = [&](double t) {
      Vertex p{m1 + t * (v[2].u1 - m1), m2 + t * (v[2].u2 - m2), 0.0};
      p.c = cost(p.u1, p.u2);
      return p;
    };
    const Vertex reflected = towards(-1.0);
    if (reflected.c < v[0].c) {
      const Vertex expanded = towards(-2.0);
      v[2] = expanded.c < reflected.c ? expanded : reflected;
    } else if (reflected.c < v[1].c) {
      v[2] = reflected;
    } else {
      const Vertex contracted = towards(reflected.c < v[2].c ? -0.5 : 0.5);
      if (contracted.c < std::min(v[2].c, reflected.c)) {
        v[2] = contracted;
      } else {
        for (int k = 1; k < 3; ++k) {
          v[k] = {0.5 * (v[0].u1 + v[k].u1), 0.5 * (v[0].u2 + v[k].u2), 0.0};
          v[k].c = cost(v[k].u1, v[k].u2);
        }
      }
    }
  }
  std::sort(v, v + 3, [](const Vertex& x, const Vertex& y) { return x.c < y.c; });
  const Vertex& b = v[0];
  const Amplitudes a = b.u1 > b.u2 ? fitAmplitudes(s, std::exp(b.u1), std::exp(b.u2)) : fitOne(s, std::exp(b.u1));
  fit.fast_rate_per_s = std::exp(b.u1);
  fit.slow_rate_per_s = std::exp(std::min(b.u2, b.u1));
  fit.fast_energy = a.fast;
  fit.slow_energy = a.slow;
}

}  // namespace

double TwoSlopeFit::crossover_s() const {
  if (!(fast_energy > 0.0 && slow_energy > 0.0) || !(fast_rate_per_s > slow_rate_per_s)) return -1.0;
  return std::log(fast_energy / slow_energy) / (fast_rate_per_s - slow_rate_per_s);
}

TwoSlopeFit fitTwoSlopes(const EnergyDecay& decay, double end_db, std::size_t max_points) {
  TwoSlopeFit fit;
  const double total = decay.energyAfter(0.0);
  if (!decay.valid() || !(total > 0.0) || !(end_db < 0.0) || max_points < 8) return fit;
  const double fs = decay.sampleRateHz();
  const double end_energy = total * std::pow(10.0, end_db / 10.0);
  // Where the curve reaches end_db: a walk in 1 ms steps up to Lundeby's crosspoint (past
  // it the curve is the noise estimate's extrapolation, not a measurement).
  const double step_s = std::max(1.0, std::floor(fs / 1000.0)) / fs;
  const double crosspoint_s = decay.lundeby().crosspoint / fs;
  double end_s = 0.0;
  while (end_s <= crosspoint_s && decay.energyAfter(end_s) > end_energy) end_s += step_s;
  if (end_s > crosspoint_s || end_s <= 0.0) return fit;
  fit.end_s = end_s;

  Samples s;
  const std::size_t count = std::min(max_points, static_cast<std::size_t>(std::floor(end_s * fs)) + 1);
  if (count < 8) return fit;
  s.dt = end_s / static_cast<double>(count - 1);
  for (std::size_t k = 0; k < count; ++k) {
    const double y = decay.energyAfter(static_cast<double>(k) * s.dt) / total;
    if (!(y > 0.0)) return fit;
    s.inverse.push_back(1.0 / y);
  }
  // Evenly spaced times put most points on the slow end of a bent curve, where the fit
  // then spends its freedom; weighting each by the curve's local fall in dB per step makes
  // every dB count alike, the first 10 dB (EDT) as much as the last.
  const std::size_t last = count - 1;
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t before = k == 0 ? 0 : k - 1, after = k == last ? last : k + 1;
    const double fall = std::log(s.inverse[after] / s.inverse[before]) / static_cast<double>(after - before);
    s.weight.push_back(std::max(fall, 1e-6));
    s.total_weight += s.weight.back();
  }
  fitSingle(s, -std::log(end_energy / total) / end_s, fit);
  fitPair(s, fit);
  fit.one_rms_error_db = rmsErrorDb(s, fit.one_rate_per_s, fit.one_energy, 0.0, 0.0);
  fit.rms_error_db = rmsErrorDb(s, fit.fast_rate_per_s, fit.fast_energy, fit.slow_rate_per_s, fit.slow_energy);
  fit.one_energy *= total;
  fit.fast_energy *= total;
  fit.slow_energy *= total;
  fit.valid = true;
  return fit;
}

}  // namespace room_reverb::core
