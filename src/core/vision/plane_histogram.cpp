#include "plane_histogram.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace room_reverb::core::layout {

PlaneHistogram::PlaneHistogram(const std::vector<double>& values, double bin_m) : bin_(bin_m), origin_(0.0) {
  if (values.empty()) {
    prefix_.assign(1, 0.0);
    return;
  }
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  origin_ = *lo - bin_;
  const auto bins = static_cast<std::size_t>(std::ceil((*hi - origin_) / bin_)) + 2;
  counts_.assign(bins, 0.0);
  for (double v : values) counts_[static_cast<std::size_t>((v - origin_) / bin_)] += 1.0;
  prefix_.assign(bins + 1, 0.0);
  for (std::size_t i = 0; i < bins; ++i) prefix_[i + 1] = prefix_[i] + counts_[i];
}

double PlaneHistogram::count(double from, double to) const {
  if (counts_.empty() || to < from) return 0.0;
  // Whole bins whose centre lies in [from, to]: exact enough at a bin of a few cm.
  const auto clampBin = [&](double x) {
    return std::clamp<long>(std::lround((x - origin_) / bin_), 0, static_cast<long>(counts_.size()));
  };
  return prefix_[clampBin(to)] - prefix_[clampBin(from)];
}

std::vector<PlanePeak> PlaneHistogram::peaks(const PlaneSpread& spread, double min_support,
                                             double min_contrast) const {
  std::vector<PlanePeak> found;
  if (counts_.empty()) return found;
  // Smooth with a Gaussian of half the narrowest window, so that a plane gives one
  // maximum rather than a comb of noisy bins.
  const double sigma_bins = std::max(1.0, 0.5 * spread.min_half_width_m / bin_);
  const int radius = static_cast<int>(std::ceil(3.0 * sigma_bins));
  std::vector<double> kernel(2 * radius + 1);
  for (int k = -radius; k <= radius; ++k) kernel[k + radius] = std::exp(-0.5 * k * k / (sigma_bins * sigma_bins));
  const int n = static_cast<int>(counts_.size());
  std::vector<double> smooth(n, 0.0);
  for (int i = 0; i < n; ++i) {
    if (counts_[i] == 0.0) continue;
    for (int k = -radius; k <= radius; ++k) {
      if (i + k >= 0 && i + k < n) smooth[i + k] += counts_[i] * kernel[k + radius];
    }
  }
  for (int i = 0; i < n; ++i) {
    if (smooth[i] <= 0.0) continue;
    const double x = origin_ + (i + 0.5) * bin_;
    const double half = spread.halfWidth(x);
    const int reach = std::max(1, static_cast<int>(std::lround(half / bin_)));
    bool is_max = true;
    for (int j = std::max(0, i - reach); j <= std::min(n - 1, i + reach) && is_max; ++j) {
      // Ties go to the lower index so a flat top yields one peak.
      if (smooth[j] > smooth[i] || (smooth[j] == smooth[i] && j < i)) is_max = false;
    }
    if (!is_max) continue;
    PlanePeak peak;
    peak.position_m = x;
    peak.support = count(x - half, x + half);
    const double flanks = count(x - 3.0 * half, x - half) + count(x + half, x + 3.0 * half);
    const double inside_density = peak.support / (2.0 * half);
    const double flank_density = flanks / (4.0 * half);
    peak.contrast = flank_density > 0.0 ? inside_density / flank_density : std::numeric_limits<double>::infinity();
    if (peak.support >= min_support && peak.contrast >= min_contrast) found.push_back(peak);
  }
  return found;
}

double refinePlanePosition(const std::vector<double>& values, const std::vector<double>& weights, double start_m,
                           double half_width_m, double* support) {
  // The weighted median from a histogram of 0.5 mm bins over the window: linear time, and
  // far finer than the noise.
  const double bin = 0.0005;
  const auto bins = static_cast<std::size_t>(std::ceil(2.0 * half_width_m / bin)) + 1;
  std::vector<double> mass(bins);
  double centre = start_m, total = 0.0;
  for (int iteration = 0; iteration < 10; ++iteration) {
    std::fill(mass.begin(), mass.end(), 0.0);
    total = 0.0;
    const double from = centre - half_width_m;
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double offset = values[i] - from;
      if (offset < 0.0 || offset > 2.0 * half_width_m) continue;
      mass[std::min(bins - 1, static_cast<std::size_t>(offset / bin))] += weights[i];
      total += weights[i];
    }
    if (total <= 0.0) break;
    double below = 0.0;
    std::size_t k = 0;
    while (k + 1 < bins && below + mass[k] < 0.5 * total) below += mass[k++];
    const double within = mass[k] > 0.0 ? (0.5 * total - below) / mass[k] : 0.5;  // where in bin k
    const double median = from + bin * (static_cast<double>(k) + within);
    const double moved = median - centre;
    centre = median;
    if (std::abs(moved) < 1e-4) break;
  }
  if (support) *support = total;
  return centre;
}

}  // namespace room_reverb::core::layout
