#include "room_reverb/metrics/lundeby.h"

#include <algorithm>
#include <cmath>

namespace room_reverb::core {
namespace {

constexpr double kFloorDb = -300.0;  // level given to exact silence
constexpr int kMaxIterations = 5;    // Lundeby: convergence within a few iterations
constexpr double kBlocksPer10Db = 5.0;        // Lundeby: 3-10 intervals per 10 dB of decay
constexpr double kNoiseMarginDb = 5.0;        // fit ends this far above the noise...
constexpr double kFitRangeDb = 20.0;          // ...and spans this much decay (10-20 dB)
constexpr double kNoiseStartBelowDb = 10.0;   // noise is measured this far past the crosspoint

double toDb(double power) { return power > 0.0 ? std::max(kFloorDb, 10.0 * std::log10(power)) : kFloorDb; }

struct Envelope {
  std::size_t block = 1;        // samples per block
  std::vector<double> level_db;  // mean-square level per block
  double timeS(std::size_t i, double fs) const { return (i + 0.5) * block / fs; }
};

// Sums of the energy from each sample to the end: every block sum and tail mean below is
// a difference of two of them, so the iterations cost one pass over the response instead
// of one each. Summed from the end, a late block is the difference of two small sums and
// keeps its precision however far it lies below the peak.
std::vector<double> tailSums(const std::vector<double>& energy) {
  std::vector<double> sums(energy.size() + 1, 0.0);
  for (std::size_t n = energy.size(); n-- > 0;) sums[n] = sums[n + 1] + energy[n];
  return sums;
}

// Mean-square level per block; `noise` is subtracted from each block's mean first.
Envelope smooth(const std::vector<double>& tail_sums, std::size_t block, double noise = 0.0) {
  Envelope env;
  env.block = std::max<std::size_t>(1, block);
  const std::size_t length = tail_sums.size() - 1;
  for (std::size_t start = 0; start + env.block <= length; start += env.block) {
    const double sum = tail_sums[start] - tail_sums[start + env.block];
    env.level_db.push_back(toDb(sum / env.block - noise));
  }
  return env;
}

double meanFrom(const std::vector<double>& tail_sums, std::size_t start) {
  const std::size_t length = tail_sums.size() - 1;
  start = std::min(start, length - 1);
  return tail_sums[start] / static_cast<double>(length - start);
}

// Least-squares line through (t_i, level_i) for i in [first, last).
bool fitLine(const Envelope& env, std::size_t first, std::size_t last, double fs,
             double& slope, double& intercept) {
  if (last <= first + 1) return false;
  double st = 0, sl = 0, stt = 0, stl = 0;
  const double n = static_cast<double>(last - first);
  for (std::size_t i = first; i < last; ++i) {
    const double t = env.timeS(i, fs);
    st += t; sl += env.level_db[i]; stt += t * t; stl += t * env.level_db[i];
  }
  const double denominator = n * stt - st * st;
  if (denominator <= 0.0) return false;
  slope = (n * stl - st * sl) / denominator;
  intercept = (sl - slope * st) / n;
  return true;
}

// First block at or after `from` whose level is at or below `level_db` (or the end).
std::size_t firstBelow(const Envelope& env, std::size_t from, double level_db) {
  for (std::size_t i = from; i < env.level_db.size(); ++i) {
    if (env.level_db[i] <= level_db) return i;
  }
  return env.level_db.size();
}

}  // namespace

LundebyResult lundebyTruncation(const std::vector<double>& energy, double fs,
                                double initial_interval_s) {
  LundebyResult result;
  const auto initial_block = static_cast<std::size_t>(std::lround(initial_interval_s * fs));
  if (energy.size() < 4 * std::max<std::size_t>(1, initial_block)) {
    result.failure = "the response is too short to follow its decay";
    return result;
  }
  const std::vector<double> sums = tailSums(energy);
  // Step 1-2: 10 ms envelope; noise from the last 10 % of the response.
  Envelope env = smooth(sums, initial_block);
  const auto peak_it = std::max_element(env.level_db.begin(), env.level_db.end());
  const std::size_t peak = static_cast<std::size_t>(peak_it - env.level_db.begin());
  result.peak_db = *peak_it;
  const std::size_t tail_start = energy.size() - energy.size() / 10;
  double noise = meanFrom(sums, tail_start);

  // Step 3-4: a first line from the peak to 10 dB above the noise, and its crosspoint.
  double slope = 0, intercept = 0;
  const std::size_t first_end = firstBelow(env, peak, toDb(noise) + 10.0);
  if (!fitLine(env, peak, first_end, fs, slope, intercept) || slope >= 0.0) {
    result.failure = "no decay above the noise floor";
    return result;
  }
  const double length_s = static_cast<double>(energy.size()) / fs;
  auto crosspointS = [&](double noise_db) {
    return std::clamp((noise_db - intercept) / slope, 0.0, length_s);
  };
  double crosspoint_s = crosspointS(toDb(noise));

  // Steps 5-9, iterated: finer intervals, noise measured past the crosspoint, the late
  // decay fitted just above the noise.
  for (int iteration = 1; iteration <= kMaxIterations; ++iteration) {
    result.iterations = iteration;
    const double interval_s = 10.0 / (-slope * kBlocksPer10Db);
    const auto block = static_cast<std::size_t>(std::lround(interval_s * fs));
    env = smooth(sums, block);
    if (env.level_db.size() < 3) break;

    const double noise_start_s = std::min(crosspoint_s + kNoiseStartBelowDb / -slope, 0.9 * length_s);
    noise = meanFrom(sums, static_cast<std::size_t>(noise_start_s * fs));
    const double noise_db = toDb(noise);

    // The fit range is chosen on the raw envelope (Lundeby), but the line is fitted to the
    // envelope with the noise power subtracted: 5 dB above the noise the raw level is
    // 1.2 dB too high, which would make the late slope too shallow.
    std::size_t env_peak = static_cast<std::size_t>(
        std::max_element(env.level_db.begin(), env.level_db.end()) - env.level_db.begin());
    const std::size_t fit_first = firstBelow(env, env_peak, noise_db + kNoiseMarginDb + kFitRangeDb);
    const std::size_t fit_last = firstBelow(env, fit_first, noise_db + kNoiseMarginDb);
    const Envelope clean = smooth(sums, block, noise);
    double new_slope = 0, new_intercept = 0;
    if (!fitLine(clean, fit_first, fit_last, fs, new_slope, new_intercept) || new_slope >= 0.0) break;
    slope = new_slope;
    intercept = new_intercept;
    const double new_crosspoint_s = crosspointS(noise_db);
    const bool converged = std::abs(new_crosspoint_s - crosspoint_s) < env.block / fs;
    crosspoint_s = new_crosspoint_s;
    if (converged) break;
  }

  result.valid = true;
  result.noise_power = noise;
  result.noise_db = toDb(noise);
  result.slope_db_per_s = slope;
  result.intercept_db = intercept;
  result.crosspoint = std::min(energy.size(), static_cast<std::size_t>(std::lround(crosspoint_s * fs)));
  return result;
}

}  // namespace room_reverb::core
