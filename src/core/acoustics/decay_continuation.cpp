#include "room_reverb/acoustics/decay_continuation.h"

#include <cmath>

namespace room_reverb::core {
namespace {

struct LineFit {
  double intercept = 0.0;
  double slope = 0.0;
};

// Least-squares line through (t_i, ln e_i), i in [first, last), t_i the bin centres.
LineFit fitLogLine(const std::vector<double>& energy, std::size_t first, std::size_t last, double bin_s) {
  double st = 0.0, sy = 0.0, stt = 0.0, sty = 0.0;
  const double n = static_cast<double>(last - first);
  for (std::size_t i = first; i < last; ++i) {
    const double t = (static_cast<double>(i) + 0.5) * bin_s;
    const double y = std::log(energy[i]);
    st += t;
    sy += y;
    stt += t * t;
    sty += t * y;
  }
  LineFit fit;
  const double denominator = n * stt - st * st;
  if (!(denominator > 0.0)) return fit;
  fit.slope = (n * sty - st * sy) / denominator;
  fit.intercept = (sy - fit.slope * st) / n;
  return fit;
}

}  // namespace

double EstablishedDecay::energyAt(double t_s) const { return std::exp(ln_energy_at_zero + rate_per_s * t_s); }

std::optional<EstablishedDecay> establishedDecay(const std::vector<double>& energy_in_flight, std::size_t complete_bins,
                                          double bin_s, const DecayContinuationOptions& options) {
  const std::vector<double>& e = energy_in_flight;
  const std::size_t n = std::min(complete_bins, e.size());
  if (n < 8 || !(e[0] > 0.0) || !(e[n - 1] > 0.0)) return std::nullopt;
  if (10.0 * std::log10(e[0] / e[n - 1]) < options.decayed_db) return std::nullopt;
  // The fitted stretch: from the first bin within straight_span_db of the last one.
  const double top = e[n - 1] * std::pow(10.0, options.straight_span_db / 10.0);
  std::size_t first = 0;
  while (first < n && e[first] > top) ++first;
  if (n - first < 6) return std::nullopt;  // too steep for this bin width to judge its shape
  for (std::size_t i = first; i < n; ++i) {
    if (!(e[i] > 0.0)) return std::nullopt;
  }
  // The bend: the two halves' slopes (ln E per second) at their centres, half the stretch
  // apart, give the rate at which the slope changes; carried on over the time the later
  // slope takes to fall another bend_horizon_db, it parts from the line by half that rate
  // times the time squared.
  const std::size_t middle = first + (n - first) / 2;
  const LineFit early = fitLogLine(e, first, middle, bin_s);
  const LineFit late = fitLogLine(e, middle, n, bin_s);
  if (!(late.slope < 0.0) || !(early.slope < 0.0)) return std::nullopt;
  constexpr double kDbPerNeper = 4.342944819032518;  // 10 log10(e): dB of an energy ratio e
  const double centres_apart_s = 0.5 * static_cast<double>(n - first) * bin_s;
  const double slope_change = (late.slope - early.slope) / centres_apart_s;
  const double horizon_s = options.bend_horizon_db / kDbPerNeper / std::abs(late.slope);
  if (kDbPerNeper * 0.5 * std::abs(slope_change) * horizon_s * horizon_s > options.bend_db) return std::nullopt;
  // The scatter about the whole stretch's line: where few rays carry the late energy (a
  // field that is not diffuse) the energy in flight wanders by tenths of a dB, and two
  // halves may agree by chance.
  const LineFit whole = fitLogLine(e, first, n, bin_s);
  double squares = 0.0;
  for (std::size_t i = first; i < n; ++i) {
    const double residual = std::log(e[i]) - (whole.intercept + whole.slope * (static_cast<double>(i) + 0.5) * bin_s);
    squares += residual * residual;
  }
  if (kDbPerNeper * std::sqrt(squares / static_cast<double>(n - first)) > options.scatter_db) return std::nullopt;
  // The line is the later half's: where the decay bends a little (within bend_db), its
  // slope is nearer to what follows than the whole stretch's.
  EstablishedDecay line;
  line.ln_energy_at_zero = late.intercept;
  line.rate_per_s = late.slope;
  line.fitted_from_s = static_cast<double>(middle) * bin_s;
  return line;
}

void continueDecay(EnergyHistogram& histogram, int band, double window_from_s, double from_s, const EstablishedDecay& line) {
  const double bin_s = histogram.binS();
  const auto window_bin = static_cast<std::size_t>(std::ceil(window_from_s / bin_s - 1e-9));
  // The bin holding from_s is modelled too: it is traced only up to from_s.
  const auto from_bin = std::min(histogram.bins(), static_cast<std::size_t>(std::floor(from_s / bin_s + 1e-9)));
  double traced = 0.0, modelled = 0.0;
  Eigen::Vector3d flux = Eigen::Vector3d::Zero();
  for (std::size_t k = window_bin; k < from_bin; ++k) {
    traced += histogram.energy(k, band);
    flux += histogram.flux(k, band);
    modelled += line.energyAt((static_cast<double>(k) + 0.5) * bin_s);
  }
  const double coupling = modelled > 0.0 && traced > 0.0 ? traced / modelled : 0.0;
  const Eigen::Vector3d direction = traced > 0.0 ? Eigen::Vector3d(flux / traced) : Eigen::Vector3d::Zero();
  for (std::size_t k = from_bin; k < histogram.bins(); ++k) {
    const double energy = coupling * line.energyAt((static_cast<double>(k) + 0.5) * bin_s);
    histogram.set(k, band, energy, energy * direction);
  }
}

}  // namespace room_reverb::core
