#include "room_reverb/rsao/lpc.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

std::vector<double> autocorrelation(const std::vector<double>& x, int max_lag) {
  if (max_lag < 0) throw InputError("autocorrelation: the maximum lag must be 0 or more");
  std::vector<double> r(static_cast<std::size_t>(max_lag) + 1, 0.0);
  for (std::size_t lag = 0; lag < r.size() && lag < x.size(); ++lag) {
    double sum = 0.0;
    for (std::size_t n = lag; n < x.size(); ++n) sum += x[n] * x[n - lag];
    r[lag] = sum;
  }
  return r;
}

std::vector<double> autocorrelationFlatBelow(const std::vector<double>& x, int max_lag, double cutoff_rad) {
  std::vector<double> r = autocorrelation(x, max_lag);
  if (!(cutoff_rad > 0.0) || x.empty() || !(r[0] > 0.0)) return r;
  // |X|^2 sampled at M >= 2 |x| points round the circle: its inverse DFT is then x's
  // autocorrelation exactly, and that of the held spectrum, a DFT of non-negative samples,
  // stays a valid (positive semi-definite) autocorrelation whatever the spectrum's range.
  // In double and directly rather than by RealFft (single precision): only max_lag + 1
  // lags of a segment of about a hundred samples are needed.
  std::size_t m = 64;
  while (m < 2 * x.size() || 2.0 * kPi / static_cast<double>(m) > cutoff_rad / 8.0) m *= 2;
  const std::size_t bins = m / 2 + 1;
  const auto powerAt = [&](double w) {
    const std::complex<double> z = std::polar(1.0, -w);
    std::complex<double> sum = 0.0;
    for (std::size_t n = x.size(); n-- > 0;) sum = sum * z + x[n];  // Horner: sum_n x[n] z^n
    return std::norm(sum);
  };
  const double held = powerAt(cutoff_rad);
  std::vector<double> power(bins);
  for (std::size_t j = 0; j < bins; ++j) {
    const double w = 2.0 * kPi * static_cast<double>(j) / static_cast<double>(m);
    power[j] = w < cutoff_rad ? held : powerAt(w);
  }
  std::vector<double> shaped(r.size(), 0.0);
  for (std::size_t k = 0; k < shaped.size(); ++k) {
    double sum = 0.0;
    for (std::size_t j = 0; j < bins; ++j) {
      const double weight = j == 0 || j + 1 == bins ? 1.0 : 2.0;  // the bins mirrored below 0
      sum += weight * power[j] * std::cos(2.0 * kPi * static_cast<double>(j * k) / static_cast<double>(m));
    }
    shaped[k] = sum / static_cast<double>(m);
  }
  // The segment's energy stays r[0]: only the shape changes.
  if (shaped[0] > 0.0) {
    const double scale = r[0] / shaped[0];
    for (double& v : shaped) v *= scale;
  }
  return shaped;
}

LpcModel levinsonDurbin(const std::vector<double>& r, int order) {
  if (order < 1) throw InputError("LPC: the prediction order must be at least 1");
  if (r.size() < static_cast<std::size_t>(order) + 1) {
    std::ostringstream os;
    os << "LPC: order " << order << " needs " << order + 1 << " autocorrelation lags, got " << r.size();
    throw InputError(os.str());
  }
  for (int i = 0; i <= order; ++i) {
    if (!std::isfinite(r[static_cast<std::size_t>(i)])) throw InputError("LPC: the autocorrelation holds NaN or infinity");
  }
  if (r[0] < 0.0) throw InputError("LPC: r[0] is negative, which no signal's autocorrelation can be");

  const auto p = static_cast<std::size_t>(order);
  LpcModel model;
  model.a.assign(p + 1, 0.0);
  model.a[0] = 1.0;
  model.reflection_coefficients.assign(p, 0.0);
  if (r[0] == 0.0) return model;  // silence: flat model, zero gain

  double error = r[0];
  std::vector<double> previous(p + 1, 0.0);
  for (std::size_t i = 1; i <= p; ++i) {
    // The error can only shrink; once it is at rounding level the segment is fully
    // predicted and a further step would divide noise by noise.
    if (error <= 1e-14 * r[0]) break;
    double acc = r[i];
    for (std::size_t j = 1; j < i; ++j) acc += model.a[j] * r[i - j];
    const double k = -acc / error;
    previous = model.a;
    for (std::size_t j = 1; j < i; ++j) model.a[j] = previous[j] + k * previous[i - j];
    model.a[i] = k;
    model.reflection_coefficients[i - 1] = k;
    error *= (1.0 - k * k);
  }
  model.gain = std::sqrt(std::max(error, 0.0));
  return model;
}

LpcModel fitLpc(const std::vector<double>& segment, int order) {
  return levinsonDurbin(autocorrelation(segment, std::max(order, 0)), order);
}

std::vector<BiquadSection> allPoleToSections(const std::vector<double>& a, double gain) {
  if (a.empty() || a[0] != 1.0) throw InputError("all-pole filter: a[0] must be 1 (normalise A(z) first)");
  // Trailing zero coefficients only lower the order (as poles at the origin they are
  // factors 1 / (1 - 0 z^-1) = 1); dropping them keeps the companion matrix non-singular.
  std::size_t p = a.size() - 1;
  while (p > 0 && a[p] == 0.0) --p;

  std::vector<BiquadSection> sections;
  std::vector<double> real_poles;
  if (p > 0) {
    // The poles are the eigenvalues of the companion matrix of z^p + a1 z^(p-1) + ... + ap.
    // That matrix is already upper Hessenberg, so its real Schur form T is computed
    // straight from it. T is quasi-triangular: a 1x1 diagonal block is a real pole, a 2x2
    // block a conjugate pair whose characteristic polynomial z^2 - trace z + det is
    // directly a section's denominator, with no complex arithmetic.
    const auto n = static_cast<Eigen::Index>(p);
    Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
    for (Eigen::Index j = 0; j < n; ++j) companion(0, j) = -a[static_cast<std::size_t>(j) + 1];
    for (Eigen::Index i = 1; i < n; ++i) companion(i, i - 1) = 1.0;
    Eigen::RealSchur<Eigen::MatrixXd> schur(n);
    schur.computeFromHessenberg(companion, Eigen::MatrixXd::Identity(n, n), false);
    if (schur.info() != Eigen::Success) throw InputError("all-pole filter: the roots of A(z) could not be found");
    const Eigen::MatrixXd& t = schur.matrixT();
    for (Eigen::Index i = 0; i < n;) {
      if (i + 1 < n && t(i + 1, i) != 0.0) {
        const double trace = t(i, i) + t(i + 1, i + 1);
        const double det = t(i, i) * t(i + 1, i + 1) - t(i, i + 1) * t(i + 1, i);
        const double half_gap = 0.5 * (t(i, i) - t(i + 1, i + 1));
        const double discriminant = half_gap * half_gap + t(i, i + 1) * t(i + 1, i);
        if (discriminant < 0.0) {
          BiquadSection s;
          s.a1 = -trace;
          s.a2 = det;
          sections.push_back(s);
        } else {  // a block with two real poles (Eigen splits these, but be safe)
          real_poles.push_back(0.5 * trace + std::sqrt(discriminant));
          real_poles.push_back(0.5 * trace - std::sqrt(discriminant));
        }
        i += 2;
      } else {
        real_poles.push_back(t(i, i));
        i += 1;
      }
    }
  }
  // Pair neighbouring real poles (sorted), so each section's poles are alike in size.
  std::sort(real_poles.begin(), real_poles.end());
  for (std::size_t i = 0; i + 1 < real_poles.size(); i += 2) {
    BiquadSection s;
    s.a1 = -(real_poles[i] + real_poles[i + 1]);
    s.a2 = real_poles[i] * real_poles[i + 1];
    sections.push_back(s);
  }
  if (real_poles.size() % 2 == 1) {
    BiquadSection s;  // the odd order's first-order section: b2 = a2 = 0
    s.a1 = -real_poles.back();
    sections.push_back(s);
  }
  if (sections.empty()) sections.emplace_back();
  sections.front().b0 = gain;
  return sections;
}

std::vector<double> filterSections(const std::vector<BiquadSection>& sections, const std::vector<double>& x) {
  std::vector<double> y = x;
  for (const auto& s : sections) {
    double z1 = 0.0, z2 = 0.0;
    for (double& v : y) {
      const double in = v;
      const double out = s.b0 * in + z1;
      z1 = s.b1 * in - s.a1 * out + z2;
      z2 = s.b2 * in - s.a2 * out;
      v = out;
    }
  }
  return y;
}

std::vector<double> filterAllPole(const std::vector<double>& a, double gain, const std::vector<double>& x) {
  if (a.empty() || a[0] != 1.0) throw InputError("all-pole filter: a[0] must be 1 (normalise A(z) first)");
  std::vector<double> y(x.size(), 0.0);
  for (std::size_t n = 0; n < x.size(); ++n) {
    double acc = gain * x[n];
    for (std::size_t i = 1; i < a.size() && i <= n; ++i) acc -= a[i] * y[n - i];
    y[n] = acc;
  }
  return y;
}

}  // namespace room_reverb::core
