#include "room_reverb/rsao/matched_arrivals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Half-width of the windowed-sinc kernel that shifts an atom by a fraction of a sample.
constexpr long kShiftHalfWidth = 8;
constexpr double kMedianOfChiSquare1 = 0.4549;
// Channel order of the residual: W, then the room axes X, Y, Z (AmbiX stores Y, Z, X).
constexpr std::array<int, 4> kChannels{kAcnW, kAcnX, kAcnY, kAcnZ};

// An arrival's shape in W and in the directional channels, each of unit energy. The
// directional shape is the direct sound's own (X, Y, Z) along its direction: a
// microphone whose directional channels respond otherwise than W (a tetrahedral array's
// B-format rolls off differently above a few kHz) then leaves nothing of an arrival in
// them when it is taken out, and its direction is not leaned by what was left.
struct Atom {
  std::vector<double> samples;      // W
  std::vector<double> directional;  // X, Y, Z along the arrival's direction
};

// A Tukey window over n samples whose cosine tapers take `taper` of the length together.
std::vector<double> tukey(std::size_t n, double taper) {
  std::vector<double> w(n, 1.0);
  const double edge = 0.5 * taper * static_cast<double>(n - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const double from_edge = std::min(static_cast<double>(i), static_cast<double>(n - 1 - i));
    if (from_edge < edge) w[i] = 0.5 - 0.5 * std::cos(kPi * from_edge / edge);
  }
  return w;
}

void normalise(std::vector<double>& x) {
  double e = 0.0;
  for (double v : x) e += v * v;
  if (e <= 0.0) return;
  const double s = 1.0 / std::sqrt(e);
  for (double& v : x) v *= s;
}

// The direct sound's atom, then copies low-passed by `passes` one-pole sections at each
// cut-off (y[n] = (1 - a) x[n] + a y[n-1], a = exp(-2 pi fc / fs): minimum phase, so the
// onset stays where it was and only the decay after it is smeared).
std::vector<Atom> makeAtoms(const std::vector<double>& direct, const std::vector<double>& directional, double fs,
                           const MatchedArrivalOptions& options) {
  std::vector<Atom> atoms{{direct, directional}};
  for (double cutoff : options.low_pass_cutoffs_hz) {
    const double a = std::exp(-2.0 * kPi * cutoff / fs);
    for (int passes = 1; passes <= options.max_low_pass_passes; ++passes) {
      // Six time constants per pass hold the filter's tail to within e^-6 in amplitude.
      const auto tail = static_cast<std::size_t>(std::ceil(6.0 * passes * fs / (2.0 * kPi * cutoff)));
      const auto lowPassed = [&](std::vector<double> x) {
        x.resize(x.size() + tail, 0.0);
        for (int p = 0; p < passes; ++p) {
          double y = 0.0;
          for (double& v : x) v = y = (1.0 - a) * v + a * y;
        }
        return x;
      };
      atoms.push_back({lowPassed(direct), lowPassed(directional)});
    }
  }
  for (Atom& atom : atoms) {
    normalise(atom.samples);
    normalise(atom.directional);
  }
  return atoms;
}

// The atom delayed by delta in [-0.5, 0.5] samples (band-limited interpolation, a Hann-
// windowed sinc): out[j] is sample j - kShiftHalfWidth of the shifted atom. Sample m of the
// atom reaches out[j] at the offset t = (j - kShiftHalfWidth - m) - delta, an integer less
// delta, so the kernel is computed once per call for the integers in reach, not per tap.
std::vector<double> shiftedAtom(const std::vector<double>& atom, double delta) {
  constexpr long kReach = kShiftHalfWidth + 1;
  std::array<double, 2 * kReach + 1> kernel{};
  for (long k = -kReach; k <= kReach; ++k) {
    const double t = static_cast<double>(k) - delta;
    if (std::abs(t) > kShiftHalfWidth) continue;
    const double sinc = std::abs(t) < 1e-12 ? 1.0 : std::sin(kPi * t) / (kPi * t);
    const double hann = 0.5 + 0.5 * std::cos(kPi * t / (kShiftHalfWidth + 1));
    kernel[static_cast<std::size_t>(k + kReach)] = sinc * hann;
  }
  std::vector<double> out(atom.size() + 2 * kShiftHalfWidth, 0.0);
  const long size = static_cast<long>(atom.size());
  for (long j = 0; j < static_cast<long>(out.size()); ++j) {
    const long centre = j - kShiftHalfWidth;  // the atom sample at offset k = 0
    double sum = 0.0;
    for (long m = std::max(0L, centre - kReach); m <= std::min(size - 1, centre + kReach); ++m) {
      sum += atom[static_cast<std::size_t>(m)] * kernel[static_cast<std::size_t>(centre - m + kReach)];
    }
    out[static_cast<std::size_t>(j)] = sum;
  }
  return out;
}

// An atom's two shapes delayed by the same fraction of a sample.
struct ShiftedAtom {
  std::vector<double> w, directional;
};

ShiftedAtom shifted(const Atom& atom, double delta) {
  return {shiftedAtom(atom.samples, delta), shiftedAtom(atom.directional, delta)};
}

class Pursuit {
 public:
  // `directional_scale`: the direct sound's W amplitude over its directional amplitude,
  // each on its own unit-energy shape (1 for an ideal microphone), so that an arrival's
  // (X, Y, Z) coefficients compare with its W coefficient as a plane wave's do.
  Pursuit(const AudioBuffer& ambix, std::size_t first, std::size_t end, std::vector<Atom> atoms, double reference,
          double directional_scale)
      : first_(first), atoms_(std::move(atoms)), reference_(reference), directional_scale_(directional_scale) {
    for (std::size_t c = 0; c < 4; ++c) {
      const auto& channel = ambix.channels[static_cast<std::size_t>(kChannels[c])];
      residual_[c].assign(channel.begin() + static_cast<long>(first), channel.begin() + static_cast<long>(end));
    }
    correlation_.resize(atoms_.size());
    std::size_t lags = 0;
    for (std::size_t a = 0; a < atoms_.size(); ++a) {
      const std::size_t n = size() >= atoms_[a].samples.size() ? size() - atoms_[a].samples.size() + 1 : 0;
      correlation_[a].assign(n, 0.0);
      lags = std::max(lags, n);
    }
    best_.assign(lags, 0.0);
    best_atom_.assign(lags, 0);
    updateCorrelation(0, static_cast<long>(size()));
  }

  std::size_t size() const { return residual_[0].size(); }
  double timeOfLag(double lag) const { return static_cast<double>(first_) + lag + reference_; }

  // Correlations of every atom with W's residual at lags [from, to), and the strongest
  // atom at each of those lags.
  void updateCorrelation(long from, long to) {
    for (std::size_t a = 0; a < atoms_.size(); ++a) {
      const auto& atom = atoms_[a].samples;
      auto& c = correlation_[a];
      for (long i = std::max(0L, from); i < std::min(static_cast<long>(c.size()), to); ++i) {
        double sum = 0.0;
        for (std::size_t m = 0; m < atom.size(); ++m) sum += atom[m] * residual_[0][static_cast<std::size_t>(i) + m];
        c[static_cast<std::size_t>(i)] = sum;
      }
    }
    for (long i = std::max(0L, from); i < std::min(static_cast<long>(best_.size()), to); ++i) {
      const auto at = static_cast<std::size_t>(i);
      best_[at] = 0.0;
      best_atom_[at] = 0;
      for (std::size_t a = 0; a < atoms_.size(); ++a) {
        if (at < correlation_[a].size() && std::abs(correlation_[a][at]) > best_[at]) {
          best_[at] = std::abs(correlation_[a][at]);
          best_atom_[at] = a;
        }
      }
    }
  }

  // The atom and lag of the largest |correlation| among lags allowed by `open`. Every
  // iteration of the pursuit asks, refused candidates included: the per-lag maximum over
  // the atoms, kept by updateCorrelation, makes it one pass over the lags.
  bool strongest(const std::vector<bool>& open, std::size_t& atom, long& lag) const {
    double best = 0.0;
    for (std::size_t i = 0; i < best_.size() && i < open.size(); ++i) {
      if (open[i] && best_[i] > best) {
        best = best_[i];
        atom = best_atom_[i];
        lag = static_cast<long>(i);
      }
    }
    return best > 0.0;
  }

  double correlation(std::size_t atom, long lag) const {
    const auto& c = correlation_[atom];
    return lag >= 0 && lag < static_cast<long>(c.size()) ? c[static_cast<std::size_t>(lag)] : 0.0;
  }

  // Sub-sample peak by a parabola through the correlation at lag - 1, lag, lag + 1.
  double refine(std::size_t atom, long lag) const {
    const double c0 = correlation(atom, lag), sign = c0 < 0.0 ? -1.0 : 1.0;
    const double cm = sign * correlation(atom, lag - 1), cp = sign * correlation(atom, lag + 1), cz = sign * c0;
    const double curvature = cm - 2.0 * cz + cp;
    if (!(curvature < 0.0)) return 0.0;
    return std::clamp(0.5 * (cm - cp) / curvature, -0.5, 0.5);
  }

  // Projections of W on the shifted atom's W shape and of X, Y, Z on its directional shape,
  // placed at lag (first sample of the unshifted atom): amplitudes per unit of each shape,
  // the directional ones scaled to W's (directional_scale). shifted_energy: the W shape's.
  std::array<double, 4> project(const ShiftedAtom& atom, long lag, double& shifted_energy) const {
    std::array<double, 4> a{};
    shifted_energy = 0.0;
    double directional_energy = 0.0;
    for (std::size_t j = 0; j < atom.w.size(); ++j) {
      const long n = lag - kShiftHalfWidth + static_cast<long>(j);
      if (n < 0 || n >= static_cast<long>(size())) continue;
      const auto at = static_cast<std::size_t>(n);
      shifted_energy += atom.w[j] * atom.w[j];
      directional_energy += atom.directional[j] * atom.directional[j];
      a[0] += atom.w[j] * residual_[0][at];
      for (std::size_t c = 1; c < 4; ++c) a[c] += atom.directional[j] * residual_[c][at];
    }
    if (shifted_energy > 0.0) a[0] /= shifted_energy;
    for (std::size_t c = 1; c < 4; ++c) a[c] = directional_energy > 0.0 ? directional_scale_ * a[c] / directional_energy : 0.0;
    return a;
  }

  // W's residual energy under the shifted atom's support, weighted by the atom's shape
  // (so that a neighbour at the atom's tapered edge counts for little).
  double supportEnergy(const ShiftedAtom& atom, long lag) const {
    const std::vector<double>& shape = atom.w;
    double peak = 0.0;
    for (double v : shape) peak = std::max(peak, std::abs(v));
    double sum = 0.0;
    for (std::size_t j = 0; j < shape.size(); ++j) {
      const long n = lag - kShiftHalfWidth + static_cast<long>(j);
      if (n < 0 || n >= static_cast<long>(size()) || peak <= 0.0) continue;
      const double r = residual_[0][static_cast<std::size_t>(n)];
      sum += std::abs(shape[j]) / peak * r * r;
    }
    return sum;
  }

  // residual -= scale * amplitude * shape at lag: W's shape in W, the directional shape in
  // X, Y and Z.
  void subtract(const ShiftedAtom& atom, long lag, const std::array<double, 4>& amplitude, double scale) {
    for (std::size_t j = 0; j < atom.w.size(); ++j) {
      const long n = lag - kShiftHalfWidth + static_cast<long>(j);
      if (n < 0 || n >= static_cast<long>(size())) continue;
      const auto at = static_cast<std::size_t>(n);
      residual_[0][at] -= scale * amplitude[0] * atom.w[j];
      for (std::size_t c = 1; c < 4; ++c) residual_[c][at] -= scale * amplitude[c] / directional_scale_ * atom.directional[j];
    }
  }

  // Power per sample of W's residual within +-span samples of sample `centre`, from the
  // median of the squared samples: for Gaussian noise the median of x^2 is 0.4549 of its
  // mean (the median of chi-square with one degree of freedom), and arrivals not yet taken
  // out, a few samples each, barely move a median where they would dominate a mean.
  double localPower(double centre, double span) const {
    const long lo = std::max(0L, static_cast<long>(std::ceil(centre - span)));
    const long hi = std::min(static_cast<long>(size()) - 1, static_cast<long>(std::floor(centre + span)));
    if (hi < lo) return 0.0;
    std::vector<double> squares;
    squares.reserve(static_cast<std::size_t>(hi - lo + 1));
    for (long n = lo; n <= hi; ++n) squares.push_back(residual_[0][static_cast<std::size_t>(n)] * residual_[0][static_cast<std::size_t>(n)]);
    auto middle = squares.begin() + static_cast<long>(squares.size() / 2);
    std::nth_element(squares.begin(), middle, squares.end());
    return *middle / kMedianOfChiSquare1;
  }

  const Atom& atom(std::size_t a) const { return atoms_[a]; }
  const std::vector<double>& residualW() const { return residual_[0]; }
  std::size_t first() const { return first_; }
  // The W the arrival's subtraction took out: amplitude times the shifted atom's W shape,
  // clipped to the span, and the RIR sample it starts at.
  std::vector<double> modelW(const ShiftedAtom& atom, long lag, double amplitude, std::size_t& first_sample) const {
    const long start = std::max(0L, lag - kShiftHalfWidth);
    const long stop = std::min(static_cast<long>(size()), lag - kShiftHalfWidth + static_cast<long>(atom.w.size()));
    first_sample = first_ + static_cast<std::size_t>(start);
    std::vector<double> out;
    for (long n = start; n < stop; ++n) out.push_back(amplitude * atom.w[static_cast<std::size_t>(n - lag + kShiftHalfWidth)]);
    return out;
  }
  std::size_t longestAtom() const {
    std::size_t n = 0;
    for (const Atom& a : atoms_) n = std::max(n, a.samples.size());
    return n;
  }
  double reference() const { return reference_; }

 private:
  std::size_t first_;
  std::vector<Atom> atoms_;
  double reference_;  // the arrival's time inside an atom, in samples from its first sample
  double directional_scale_;
  std::array<std::vector<double>, 4> residual_;
  std::vector<std::vector<double>> correlation_;
  std::vector<double> best_;            // max over atoms of |correlation| at each lag
  std::vector<std::size_t> best_atom_;  // the atom that holds it (the first, at a tie)
};

Eigen::Vector3d directionOf(const std::array<double, 4>& a) {
  Eigen::Vector3d v(a[1], a[2], a[3]);
  if (a[0] < 0.0) v = -v;
  return v.norm() > 0.0 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d::UnitX();
}

// The window directness of CardioidSteeringStatistics, 2 |p| / (E_ww + tr R), of the
// arrival's own projection: 2 |a_W| |a_XYZ| / (a_W^2 + |a_XYZ|^2), 1 for a plane wave in
// SN3D (|a_XYZ| = |a_W|), less where a neighbour or the diffuse field left the directional
// channels more or less than W.
double projectionDirectness(const std::array<double, 4>& a) {
  const double w2 = a[0] * a[0], xyz2 = a[1] * a[1] + a[2] * a[2] + a[3] * a[3];
  return w2 + xyz2 > 0.0 ? 2.0 * std::sqrt(w2 * xyz2) / (w2 + xyz2) : 0.0;
}

}  // namespace

void validateMatchedArrivalOptions(const MatchedArrivalOptions& o) {
  std::ostringstream os;
  os << "matched arrivals: ";
  if (!(o.template_before_s >= 0.0 && o.template_after_s > 0.0 && o.template_before_s + o.template_after_s <= 0.01)) {
    os << "template_before_s = " << o.template_before_s << ", template_after_s = " << o.template_after_s
       << "; use a short span around the direct sound, e.g. 0.00025 s each (at most 10 ms together)";
  } else if (std::any_of(o.low_pass_cutoffs_hz.begin(), o.low_pass_cutoffs_hz.end(),
                         [](double f) { return !(f > 0.0 && f < 24000.0); })) {
    os << "low_pass_cutoffs_hz must be in (0, 24000) Hz, e.g. 6000, 3000, 1500";
  } else if (o.max_low_pass_passes < 0 || o.max_low_pass_passes > 4) {
    os << "max_low_pass_passes = " << o.max_low_pass_passes << "; use 0 to 4, e.g. 2";
  } else if (!std::isfinite(o.min_detection_snr_db)) {
    os << "min_detection_snr_db must be finite, e.g. 15";
  } else if (!(o.min_explained_share >= 0.0 && o.min_explained_share <= 1.0)) {
    os << "min_explained_share = " << o.min_explained_share << "; use 0 to 1, e.g. 0.5";
  } else if (!(o.noise_span_s > 0.0 && o.noise_span_s <= 0.05)) {
    os << "noise_span_s = " << o.noise_span_s << " s; use (0, 0.05] s, e.g. 0.002";
  } else if (!(o.min_separation_s >= 0.0 && o.min_separation_s <= 0.01)) {
    os << "min_separation_s = " << o.min_separation_s << " s; use 0 to 0.01 s, e.g. 0.0001";
  } else if (!(o.direct_guard_s >= 0.0 && o.direct_guard_s <= 0.01)) {
    os << "direct_guard_s = " << o.direct_guard_s << " s; use 0 to 0.01 s, e.g. 0.0002";
  } else if (!(o.relative_threshold_db <= 0.0) || !std::isfinite(o.relative_threshold_db)) {
    os << "relative_threshold_db = " << o.relative_threshold_db << "; use a finite level at or below 0 dB, e.g. -30";
  } else {
    return;
  }
  throw InputError(os.str());
}

std::vector<MatchedArrival> matchedPursuitArrivals(const AudioBuffer& ambix, double direct_time_s, double end_s,
                                                   const MatchedArrivalOptions& options) {
  return matchedPursuit(ambix, direct_time_s, end_s, options).arrivals;
}

MatchedPursuit matchedPursuit(const AudioBuffer& ambix, double direct_time_s, double end_s,
                              const MatchedArrivalOptions& options) {
  validateMatchedArrivalOptions(options);
  if (ambix.channelCount() < 4) {
    throw InputError("matched arrivals: needs first-order B-format (4 channels, AmbiX W, Y, Z, X), got " +
                     std::to_string(ambix.channelCount()) + " channel(s)");
  }
  const double fs = ambix.sample_rate_hz;
  const auto frames = static_cast<long>(ambix.frameCount());
  const double direct_sample = direct_time_s * fs;

  // The direct sound's atom, cut from W.
  const long cut_first = std::max(0L, static_cast<long>(std::floor(direct_sample - options.template_before_s * fs)));
  const long cut_last = std::min(frames - 1, static_cast<long>(std::ceil(direct_sample + options.template_after_s * fs)));
  std::vector<double> direct(static_cast<std::size_t>(cut_last - cut_first + 1));
  const std::vector<double> taper = tukey(direct.size(), 2.0 / 3.0);
  Eigen::Vector3d intensity = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> xyz(direct.size());
  for (std::size_t i = 0; i < direct.size(); ++i) {
    const auto n = static_cast<std::size_t>(cut_first) + i;
    direct[i] = taper[i] * ambix.channels[kAcnW][n];
    xyz[i] = taper[i] * Eigen::Vector3d(ambix.channels[kAcnX][n], ambix.channels[kAcnY][n], ambix.channels[kAcnZ][n]);
    intensity += direct[i] * xyz[i];
  }
  // The directional shape: (X, Y, Z) along the direct sound's intensity. Its norm against
  // W's is the microphone's directional gain, which the projections divide out.
  const Eigen::Vector3d u = intensity.norm() > 0.0 ? Eigen::Vector3d(intensity.normalized()) : Eigen::Vector3d::UnitX();
  std::vector<double> directional(direct.size());
  double w_norm = 0.0, directional_norm = 0.0;
  for (std::size_t i = 0; i < direct.size(); ++i) {
    directional[i] = u.dot(xyz[i]);
    w_norm += direct[i] * direct[i];
    directional_norm += directional[i] * directional[i];
  }
  const double directional_scale =
      directional_norm > 0.0 && w_norm > 0.0 ? std::sqrt(w_norm / directional_norm) : 1.0;
  if (!(directional_norm > 0.0)) directional = direct;
  std::vector<Atom> atoms = makeAtoms(direct, directional, fs, options);

  const long longest = static_cast<long>(std::max_element(atoms.begin(), atoms.end(), [](const Atom& a, const Atom& b) {
                                           return a.samples.size() < b.samples.size();
                                         })->samples.size());
  const long first = std::max(0L, cut_first - kShiftHalfWidth - 1);
  const long end = std::min(frames, static_cast<long>(std::ceil(end_s * fs)) + longest + kShiftHalfWidth + 1);
  Pursuit pursuit(ambix, static_cast<std::size_t>(first), static_cast<std::size_t>(end), std::move(atoms),
                  direct_sample - static_cast<double>(cut_first), directional_scale);

  std::vector<MatchedArrival> result;
  const double span = options.noise_span_s * fs;
  const long reach = static_cast<long>(pursuit.longestAtom()) + 2 * kShiftHalfWidth + 2;

  // The direct sound first, at its own time, with its own shape.
  const long direct_lag = cut_first - first;
  {
    double energy = 0.0;
    const ShiftedAtom shifted_atom = shifted(pursuit.atom(0), 0.0);
    const auto a = pursuit.project(shifted_atom, direct_lag, energy);
    pursuit.subtract(shifted_atom, direct_lag, a, 1.0);
    pursuit.updateCorrelation(direct_lag - reach, direct_lag + reach);
    MatchedArrival m;
    m.time_s = direct_time_s;
    m.amplitude = a[0] * std::sqrt(energy);
    m.direction = directionOf(a);
    m.directness = projectionDirectness(a);
    const double noise = pursuit.localPower(static_cast<double>(direct_lag) + pursuit.reference(), span);
    m.snr_db = noise > 0.0 ? 10.0 * std::log10(m.amplitude * m.amplitude / noise) : 300.0;
    m.w_model = pursuit.modelW(shifted_atom, direct_lag, a[0], m.w_first);
    result.push_back(m);
  }
  const double floor = std::abs(result.front().amplitude) * std::pow(10.0, options.relative_threshold_db / 20.0);
  const double min_snr = std::pow(10.0, options.min_detection_snr_db / 10.0);
  const long separation = static_cast<long>(std::ceil(options.min_separation_s * fs));

  // Lags whose arrival time lies after the direct sound (by its guard and the separation)
  // and by end_s.
  const double first_s = direct_time_s + std::max(options.min_separation_s, options.direct_guard_s);
  std::vector<bool> open(pursuit.size(), false);
  for (std::size_t i = 0; i < open.size(); ++i) {
    const double t = pursuit.timeOfLag(static_cast<double>(i)) / fs;
    open[i] = t >= first_s && t <= end_s;
  }
  const auto close = [&](long lag) {
    for (long i = std::max(0L, lag - separation); i <= std::min(static_cast<long>(open.size()) - 1, lag + separation); ++i)
      open[static_cast<std::size_t>(i)] = false;
  };
  // Candidates refused for too little SNR, tried again (up to kRetries times) once an
  // arrival within reach of their noise span is taken out: the refusal may have come from
  // that neighbour's power, not from noise.
  constexpr int kRetries = 3;
  struct Refused {
    long lag;
    int tries;
  };
  std::vector<Refused> refused;
  std::vector<long> accepted;
  const auto reopenNear = [&](long lag) {
    const long reach_noise = static_cast<long>(std::ceil(span)) + reach;
    for (Refused& r : refused) {
      if (r.tries >= kRetries || std::abs(r.lag - lag) > reach_noise) continue;
      const bool taken = std::any_of(accepted.begin(), accepted.end(), [&](long a) { return std::abs(a - r.lag) <= separation; });
      if (taken) continue;
      ++r.tries;
      for (long i = std::max(0L, r.lag - separation); i <= std::min(static_cast<long>(open.size()) - 1, r.lag + separation); ++i) {
        const double t = pursuit.timeOfLag(static_cast<double>(i)) / fs;
        const bool near_accepted = std::any_of(accepted.begin(), accepted.end(), [&](long a) { return std::abs(a - i) <= separation; });
        open[static_cast<std::size_t>(i)] = !near_accepted && t >= first_s && t <= end_s;
      }
    }
  };

  for (std::size_t iteration = 0; iteration < options.max_iterations; ++iteration) {
    std::size_t atom = 0;
    long lag = 0;
    if (!pursuit.strongest(open, atom, lag)) break;
    if (std::abs(pursuit.correlation(atom, lag)) < floor) break;
    const double delta = pursuit.refine(atom, lag);
    const ShiftedAtom shifted_atom = shifted(pursuit.atom(atom), delta);
    double energy = 0.0;
    const auto a = pursuit.project(shifted_atom, lag, energy);
    const double support_before = pursuit.supportEnergy(shifted_atom, lag);
    pursuit.subtract(shifted_atom, lag, a, 1.0);
    const double centre = static_cast<double>(lag) + delta + pursuit.reference();
    const double noise = pursuit.localPower(centre, span);
    const double peak = a[0] * a[0] * energy;  // the matched filter's output power
    close(lag);
    // DYPSA's phase-slope test in matched-filter terms: a true arrival carries most of the
    // residual's energy where its atom lies; what a mismatched atom leaves of a strong
    // arrival (a different low-pass, a loudspeaker's ringing) is spread, not a pulse.
    const bool pulse_like = peak >= options.min_explained_share * support_before;
    if ((noise > 0.0 && peak < min_snr * noise) || !pulse_like) {
      pursuit.subtract(shifted_atom, lag, a, -1.0);  // not an arrival (yet): put it back
      const auto known = std::find_if(refused.begin(), refused.end(), [&](const Refused& r) { return std::abs(r.lag - lag) <= separation; });
      if (known == refused.end()) refused.push_back({lag, 0});
      continue;
    }
    pursuit.updateCorrelation(lag - reach, lag + reach);
    accepted.push_back(lag);
    reopenNear(lag);
    MatchedArrival m;
    m.time_s = pursuit.timeOfLag(static_cast<double>(lag) + delta) / fs;
    m.amplitude = a[0] * std::sqrt(energy);
    m.direction = directionOf(a);
    m.directness = projectionDirectness(a);
    m.snr_db = noise > 0.0 ? 10.0 * std::log10(peak / noise) : 300.0;
    m.atom = atom;
    m.w_model = pursuit.modelW(shifted_atom, lag, a[0], m.w_first);
    result.push_back(m);
  }
  std::sort(result.begin() + 1, result.end(),
            [](const MatchedArrival& x, const MatchedArrival& y) { return x.time_s < y.time_s; });
  return {std::move(result), pursuit.residualW(), pursuit.first()};
}

}  // namespace room_reverb::core
