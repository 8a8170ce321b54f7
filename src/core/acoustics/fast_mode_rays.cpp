#include "room_reverb/acoustics/fast_mode_rays.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "room_reverb/common/error.h"
#include "room_reverb/common/hash_mix.h"
#include "room_reverb/common/sample_statistics.h"

namespace room_reverb::core {
namespace {

// The bands whose T20 the fast mode is held to (125 Hz to 4 kHz: indices 1-6 of the nine).
constexpr int kFirstJudgedBand = 1;
constexpr int kLastJudgedBand = 6;

std::uint32_t batchSeed(std::uint32_t seed, std::size_t batch) {
  if (batch == 0) return seed;
  return static_cast<std::uint32_t>(mixBits((static_cast<std::uint64_t>(seed) << 32) ^ (0xfa57ull + batch)) >> 32);
}

// A batch's share: each batch's energies are shares of its own emission, so the total's
// are their mean, weighted by the batches' rays.
void addBatchStats(RayTracingStats& total, const RayTracingStats& part) {
  const double before = static_cast<double>(total.rays);
  const double added = static_cast<double>(part.rays);
  for (int b = 0; b < kOctaveBandCount; ++b) {
    total.energy_left_at_time_limit[b] =
        (total.energy_left_at_time_limit[b] * before + part.energy_left_at_time_limit[b] * added) / (before + added);
    total.traced_until_s[b] = std::max(total.traced_until_s[b], part.traced_until_s[b]);
  }
  addRayCounts(total, part);
  total.receiver_radius_m = part.receiver_radius_m;
}

// `mean` (over `before` rays so far) becomes the mean with `part` (over `added` more).
void averageIn(std::vector<OctaveBandValues>& mean, const std::vector<OctaveBandValues>& part, double before, double added) {
  if (mean.empty()) mean.assign(part.size(), OctaveBandValues{});
  for (std::size_t bin = 0; bin < mean.size(); ++bin) {
    for (int b = 0; b < kOctaveBandCount; ++b) mean[bin][b] = (mean[bin][b] * before + part[bin][b] * added) / (before + added);
  }
}

bool ratesKnown(const std::vector<std::array<std::optional<double>, kOctaveBandCount>>& rates, double tolerance) {
  for (int b = kFirstJudgedBand; b <= kLastJudgedBand; ++b) {
    std::vector<double> values;
    for (const auto& batch : rates) {
      if (batch[b]) values.push_back(*batch[b]);
    }
    // A band that falls too little to give a rate in most batches has nothing to judge by.
    if (values.size() * 2 < rates.size()) continue;
    if (values.size() < 2) return false;
    const double mean = sampleMean(values);
    const double standard_error = sampleStandardDeviation(values) / std::sqrt(static_cast<double>(values.size()));
    if (!(standard_error <= tolerance * std::abs(mean))) return false;
  }
  return true;
}

// The stretch of a band's energy in flight that T20 reads: from the first bin 5 dB below
// where it starts to the bin before the first one more than 25 dB below it (or the trace's
// end, or a bin with no energy), and the lowest level before that, dB.
struct FallSpan {
  std::size_t first = 0, end = 0;
  double lowest_db = 0.0;
};
std::optional<FallSpan> fallFrom5To25Db(const std::vector<OctaveBandValues>& energy_in_flight, int band) {
  if (energy_in_flight.empty() || !(energy_in_flight.front()[band] > 0.0)) return std::nullopt;
  const double start = energy_in_flight.front()[band];
  FallSpan span;
  bool found = false;
  std::size_t bin = 0;
  for (; bin < energy_in_flight.size(); ++bin) {
    const double e = energy_in_flight[bin][band];
    if (!(e > 0.0)) break;
    const double level = 10.0 * std::log10(e / start);
    if (level < -25.0) break;
    span.lowest_db = std::min(span.lowest_db, level);
    if (level <= -5.0 && !found) {
      span.first = bin;
      found = true;
    }
  }
  if (!found) return std::nullopt;
  span.end = bin;
  return span;
}

// Where each judged band's mean energy in flight falls from 5 to 25 dB below its start
// (or to the lowest it reaches): the cells' shares of the energy launched there, averaged
// over the bands that fall that far.
std::optional<std::array<double, kLaunchCells>> lateShares(const std::vector<OctaveBandValues>& in_flight, double bin_s,
                                                         const std::vector<OctaveBandValues>& by_cell) {
  const std::size_t cell_bins = by_cell.size() / kLaunchCells;
  std::array<double, kLaunchCells> shares{};
  int bands = 0;
  for (int b = kFirstJudgedBand; b <= kLastJudgedBand; ++b) {
    const std::optional<FallSpan> span = fallFrom5To25Db(in_flight, b);
    if (!span || span->end <= span->first + 1) continue;
    const auto first = static_cast<std::size_t>((static_cast<double>(span->first) + 0.5) * bin_s / kLaunchCellBinS);
    const auto last = std::min(cell_bins - 1, static_cast<std::size_t>((static_cast<double>(span->end) - 0.5) * bin_s / kLaunchCellBinS));
    std::array<double, kLaunchCells> energy{};
    double total = 0.0;
    for (std::size_t c = 0; c < kLaunchCells; ++c) {
      for (std::size_t k = first; k <= last; ++k) energy[c] += by_cell[c * cell_bins + k][b];
      total += energy[c];
    }
    if (!(total > 0.0)) continue;
    for (std::size_t c = 0; c < kLaunchCells; ++c) shares[c] += energy[c] / total;
    ++bands;
  }
  if (bands == 0) return std::nullopt;
  double sum = 0.0;
  for (double v : shares) sum += v;
  for (double& v : shares) v /= sum;
  return shares;
}

}  // namespace

std::optional<double> energyDecayRateDbPerS(const std::vector<OctaveBandValues>& energy_in_flight, int band,
                                            double bin_s) {
  // The levels from 5 dB down to 25 dB down (or the lowest reached), in dB against time.
  const std::optional<FallSpan> span = fallFrom5To25Db(energy_in_flight, band);
  if (!span || span->lowest_db > -15.0) return std::nullopt;
  const double start = energy_in_flight.front()[band];
  double sum_t = 0.0, sum_l = 0.0, sum_tt = 0.0, sum_tl = 0.0;
  std::size_t n = 0;
  for (std::size_t bin = span->first; bin < span->end; ++bin) {
    const double level = 10.0 * std::log10(energy_in_flight[bin][band] / start);
    if (level > -5.0) continue;
    const double t = (static_cast<double>(bin) + 0.5) * bin_s;
    sum_t += t;
    sum_l += level;
    sum_tt += t * t;
    sum_tl += t * level;
    ++n;
  }
  if (n < 3) return std::nullopt;
  const double denominator = static_cast<double>(n) * sum_tt - sum_t * sum_t;
  if (!(denominator > 0.0)) return std::nullopt;
  const double slope = (static_cast<double>(n) * sum_tl - sum_t * sum_l) / denominator;
  if (!(slope < 0.0)) return std::nullopt;
  return slope;
}

FastModeTrace traceFastModeDecay(const AcousticScene& scene, const Eigen::Vector3d& source,
                                 const Eigen::Vector3d& listener, const PropagationModel& model,
                                 const RayTracingOptions& rays, std::size_t max_rays, const FastRayOptions& options) {
  if (max_rays == 0) throw InputError("the fast mode's ray count must be at least 1");
  if (!std::isfinite(options.rate_tolerance)) throw InputError("the fast mode's rate tolerance must be finite");
  if (!(options.track_radius_m > 0.0) || !std::isfinite(options.track_radius_m)) {
    throw InputError("the fast mode's track receiver needs a positive radius in metres");
  }
  if (!(options.late_launch_mixture >= 0.0 && options.late_launch_mixture < 1.0)) {
    throw InputError("the fast mode's late launch mixture must be in [0, 1)");
  }
  const auto one_run = [&](std::size_t count, std::shared_ptr<const LaunchDensity> density = nullptr) {
    RayTracingOptions all = rays;
    all.launch_density = std::move(density);
    all.ray_count = count;
    all.track_radius_m = options.track_radius_m;
    all.record_energy_in_flight = false;  // its receiver is heard, not the room's mean
    RayTracingResult traced = traceRays(scene, source, listener, model, all);
    FastModeTrace out;
    out.stats = traced.stats;
    out.batches = 1;
    out.receiver = std::move(traced.histogram);
    out.launch_density = all.launch_density;
    return out;
  };
  if (!(options.rate_tolerance > 0.0) || max_rays <= options.min_rays) return one_run(max_rays);
  if (!(options.reflection_budget > 0.0)) throw InputError("the fast mode's reflection budget must be positive");
  if (options.batch_rays == 0) throw InputError("the fast mode's batch of rays must hold at least 1");
  // The pilot: min_rays in batches, each batch's fall one decay rate per band.
  FastModeTrace pilot;
  std::vector<std::array<std::optional<double>, kOctaveBandCount>> rates;
  std::size_t traced_rays = 0;
  std::vector<OctaveBandValues> by_cell;
  while (traced_rays < options.min_rays) {
    RayTracingOptions batch = rays;
    batch.record_launch_cells = options.late_launch_mixture > 0.0;
    batch.launch_density = nullptr;  // the pilot launches uniformly
    batch.ray_count = std::min(options.batch_rays, options.min_rays - traced_rays);
    batch.seed = batchSeed(rays.seed, pilot.batches);
    RayTracingResult traced = traceRays(scene, source, listener, model, batch);
    const double before = static_cast<double>(traced_rays), added = static_cast<double>(batch.ray_count);
    averageIn(pilot.energy_in_flight, traced.energy_in_flight, before, added);
    averageIn(pilot.late_energy_in_flight, traced.late_energy_in_flight, before, added);
    if (batch.record_launch_cells) averageIn(by_cell, traced.energy_in_flight_by_launch_cell, before, added);
    std::array<std::optional<double>, kOctaveBandCount> batch_rates;
    for (int b = 0; b < kOctaveBandCount; ++b) batch_rates[b] = energyDecayRateDbPerS(traced.energy_in_flight, b, batch.bin_s);
    rates.push_back(batch_rates);
    addBatchStats(pilot.stats, traced.stats);
    traced_rays += batch.ray_count;
    ++pilot.batches;
  }
  if (ratesKnown(rates, options.rate_tolerance)) return pilot;
  // Not known: one run of as many rays as the budget buys. Batches are not traced on
  // instead: where the late sound rides on a few grazing paths, 16 batches of 500 rays
  // read T20 10-30 % longer than one run of 8000 in the sample room, the carpeted room and
  // the corridor of scripts/fast-mode-check, further from the accurate mode there.
  const double per_ray = static_cast<double>(pilot.stats.reflections) / static_cast<double>(traced_rays);
  std::size_t count = max_rays;
  if (per_ray * static_cast<double>(max_rays) > options.reflection_budget) {
    count = std::max(traced_rays, static_cast<std::size_t>(options.reflection_budget / per_ray));
  }
  std::shared_ptr<const LaunchDensity> density;
  if (options.late_launch_mixture > 0.0) {
    if (const auto shares = lateShares(pilot.energy_in_flight, rays.bin_s, by_cell)) {
      density = std::make_shared<LaunchDensity>(lateEnergyDensity(*shares, options.late_launch_mixture));
    }
  }
  return one_run(count, density);
}

}  // namespace room_reverb::core
