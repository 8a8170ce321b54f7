#include "room_reverb/rsao/group_delay_onsets.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

std::size_t groupDelayWindowLength(double window_s, double sample_rate_hz) {
  const auto half = static_cast<std::size_t>(std::max(1.0, std::round(0.5 * window_s * sample_rate_hz)));
  return 2 * half + 1;
}

// Why the time-domain centroid and not an FFT: the energy-weighted group delay (Naylor et
// al. 2007) is the power-weighted mean over frequency of tau(w) = -dphi/dw,
// int |X(w)|^2 tau(w) dw / int |X(w)|^2 dw, and by Parseval and the derivative rule of the
// Fourier transform that equals the energy centroid of the windowed segment,
// sum_m m (w x)^2 / sum_m (w x)^2. The centroid is exact (an FFT would sample the integral
// on its bins and wrap the segment circularly), needs no phase unwrapping, does not blow
// up at spectral nulls (where the per-bin group delay is undefined) and costs one pass
// over a 49-sample window per centre, less than an FFT of the segment would.
GroupDelayFunction energyWeightedGroupDelay(const std::vector<float>& x, double sample_rate_hz,
                                            std::size_t first_centre, std::size_t end_centre,
                                            std::size_t window_length) {
  constexpr double kPi = 3.14159265358979323846;
  if (window_length < 3 || window_length % 2 == 0) {
    throw InputError("group delay: the window length must be odd and at least 3 samples");
  }
  const long half = static_cast<long>(window_length / 2);
  // Squared Hamming weights (the group delay is that of the windowed segment w x); the
  // Hamming of length window_length + 2 without its two end points, so none is wasted.
  std::vector<double> w2(window_length);
  for (long m = -half; m <= half; ++m) {
    const double w = 0.54 + 0.46 * std::cos(kPi * static_cast<double>(m) / static_cast<double>(half + 1));
    w2[static_cast<std::size_t>(m + half)] = w * w;
  }
  GroupDelayFunction gd;
  gd.sample_rate_hz = sample_rate_hz;
  gd.first_centre = first_centre;
  const std::size_t count = end_centre > first_centre ? end_centre - first_centre : 0;
  gd.delay_samples.assign(count, 0.0);
  gd.local_energy.assign(count, 0.0);
  const long size = static_cast<long>(x.size());
  for (std::size_t i = 0; i < count; ++i) {
    const long centre = static_cast<long>(first_centre + i);
    double energy = 0.0, moment = 0.0;
    for (long m = std::max(-half, -centre); m <= half && centre + m < size; ++m) {
      const double v = x[static_cast<std::size_t>(centre + m)];
      const double e = w2[static_cast<std::size_t>(m + half)] * v * v;
      energy += e;
      moment += static_cast<double>(m) * e;
    }
    gd.local_energy[i] = energy;
    gd.delay_samples[i] = energy > 0.0 ? moment / energy : 0.0;
  }
  return gd;
}

std::vector<ArrivalCandidate> negativeGoingZeroCrossings(const GroupDelayFunction& gd) {
  std::vector<ArrivalCandidate> out;
  for (std::size_t i = 0; i + 1 < gd.delay_samples.size(); ++i) {
    const double d0 = gd.delay_samples[i], d1 = gd.delay_samples[i + 1];
    if (!(d0 > 0.0 && d1 <= 0.0)) continue;
    const double fraction = d0 / (d0 - d1);
    ArrivalCandidate c;
    c.time_s = (static_cast<double>(gd.first_centre + i) + fraction) / gd.sample_rate_hz;
    c.local_energy = (1.0 - fraction) * gd.local_energy[i] + fraction * gd.local_energy[i + 1];
    c.slope = d1 - d0;
    out.push_back(c);
  }
  return out;
}

namespace {

// Largest local energy of gd within +-neighbourhood samples of a time.
double neighbourhoodPeak(const GroupDelayFunction& gd, double time_s, double neighbourhood_samples) {
  const double centre = time_s * gd.sample_rate_hz - static_cast<double>(gd.first_centre);
  const double lo = std::max(0.0, std::ceil(centre - neighbourhood_samples));
  const double hi = std::min(static_cast<double>(gd.local_energy.size()) - 1.0, std::floor(centre + neighbourhood_samples));
  double peak = 0.0;
  if (hi < lo) return peak;
  for (auto i = static_cast<std::size_t>(lo); i <= static_cast<std::size_t>(hi); ++i) peak = std::max(peak, gd.local_energy[i]);
  return peak;
}

}  // namespace

std::vector<ArrivalCandidate> pruneCandidates(const std::vector<ArrivalCandidate>& candidates,
                                              const GroupDelayFunction& gd, double reference_energy,
                                              const GroupDelayOnsetOptions& options) {
  const double floor = reference_energy * std::pow(10.0, options.relative_threshold_db / 10.0);
  const double peak_fraction = std::pow(10.0, -options.peak_margin_db / 10.0);
  const double neighbourhood = options.peak_neighbourhood_s * gd.sample_rate_hz;
  std::vector<ArrivalCandidate> by_energy;
  for (const auto& c : candidates) {
    if (!(c.local_energy >= floor && c.local_energy > 0.0)) continue;
    if (std::abs(c.slope + 1.0) > options.max_slope_deviation) continue;
    if (c.local_energy < peak_fraction * neighbourhoodPeak(gd, c.time_s, neighbourhood)) continue;
    by_energy.push_back(c);
  }
  std::stable_sort(by_energy.begin(), by_energy.end(),
                   [](const ArrivalCandidate& a, const ArrivalCandidate& b) { return a.local_energy > b.local_energy; });
  std::vector<ArrivalCandidate> kept;
  for (const auto& c : by_energy) {
    const bool near_stronger = std::any_of(kept.begin(), kept.end(), [&](const ArrivalCandidate& k) {
      return std::abs(k.time_s - c.time_s) < options.min_separation_s;
    });
    if (!near_stronger) kept.push_back(c);
  }
  std::sort(kept.begin(), kept.end(), [](const ArrivalCandidate& a, const ArrivalCandidate& b) { return a.time_s < b.time_s; });
  return kept;
}

void validateGroupDelayOnsetOptions(const GroupDelayOnsetOptions& options) {
  std::ostringstream os;
  if (!(options.window_s > 0.0) || options.window_s > 0.05) {
    os << "group delay window_s = " << options.window_s << " s; use a short window, e.g. 0.001 s (at most 0.05 s)";
  } else if (!(options.min_separation_s >= 0.0) || !std::isfinite(options.min_separation_s)) {
    os << "group delay min_separation_s = " << options.min_separation_s << " s; use 0 or more, e.g. 0.0005 s";
  } else if (!(options.relative_threshold_db <= 0.0) || !std::isfinite(options.relative_threshold_db)) {
    os << "group delay relative_threshold_db = " << options.relative_threshold_db
       << "; use a finite level at or below 0 dB, e.g. -40";
  } else if (!(options.peak_neighbourhood_s >= 0.0) || options.peak_neighbourhood_s > 0.05) {
    os << "group delay peak_neighbourhood_s = " << options.peak_neighbourhood_s << " s; use 0 to 0.05 s, e.g. 0.0005";
  } else if (!(options.peak_margin_db >= 0.0) || !std::isfinite(options.peak_margin_db)) {
    os << "group delay peak_margin_db = " << options.peak_margin_db << "; use a finite margin of 0 dB or more, e.g. 6";
  } else if (!(options.max_slope_deviation > 0.0) || !std::isfinite(options.max_slope_deviation)) {
    os << "group delay max_slope_deviation = " << options.max_slope_deviation << "; use a positive number, e.g. 0.5";
  } else {
    return;
  }
  throw InputError(os.str());
}

}  // namespace room_reverb::core
