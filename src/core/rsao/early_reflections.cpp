#include "room_reverb/rsao/early_reflections.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/common/error.h"
#include "room_reverb/metrics/onset.h"
#include "room_reverb/rsao/analysis_window.h"
#include "room_reverb/rsao/direction_of_arrival.h"

namespace room_reverb::core {
namespace {

constexpr const char* kWhat = "early reflections";
constexpr double kPi = 3.14159265358979323846;
constexpr double kDirectSearchBeforeS = 0.0005;  // the onset sample may sit on a pulse's rising edge
constexpr double kDirectSearchAfterS = 0.001;
constexpr double kMinimumDurationS = 0.01;

void requireInput(bool ok, const std::string& message) {
  if (!ok) throw InputError(std::string(kWhat) + ": " + message);
}

void validateInput(const AudioBuffer& ambix, const EarlyReflectionOptions& options) {
  {
    std::ostringstream os;
    os << "needs first-order B-format, at least 4 channels (AmbiX: W, Y, Z, X), got " << ambix.channelCount()
       << " channel(s); convert FuMa or A-format to AmbiX first";
    requireInput(ambix.channelCount() >= 4, os.str());
  }
  validateAudioBuffer(ambix, std::string(kWhat) + ": the impulse response");
  {
    std::ostringstream os;
    os << "the impulse response is at " << ambix.sample_rate_hz
       << " Hz; resample it to 48000 Hz first (the RSAO time base)";
    requireInput(ambix.sample_rate_hz == kInternalSampleRateHz, os.str());
  }
  {
    const double needed_s = std::max(kMinimumDurationS, options.analysis_window_s);
    std::ostringstream os;
    os << "the impulse response is too short: " << ambix.frameCount() << " samples ("
       << 1000.0 * ambix.durationS() << " ms); it needs at least " << 1000.0 * needed_s << " ms";
    requireInput(ambix.durationS() >= needed_s, os.str());
  }
  const auto& w = ambix.channels[kAcnW];
  requireInput(std::any_of(w.begin(), w.end(), [](float v) { return v != 0.0f; }),
               "the W channel (ACN 0) is silent, every sample is zero; check the recording and the channel order");
}

// Level, direction and spectral shape of the arrival at time_s, over the analysis window;
// `w_at(n)` gives sample n of the W it is measured on (the RIR's, or one arrival alone).
template <class WAt>
EarlyReflection analyseArrival(const AudioBuffer& ambix, double time_s, const EarlyReflectionOptions& options,
                               const WAt& w_at) {
  const double fs = ambix.sample_rate_hz;
  const SampleWindow window = hammingWindowAt(time_s * fs, options.analysis_window_s * fs, ambix.frameCount());
  std::vector<double> segment(window.weights.size());
  double energy = 0.0;
  for (std::size_t i = 0; i < segment.size(); ++i) {
    segment[i] = window.weights[i] * w_at(window.first + i);
    energy += segment[i] * segment[i];
  }
  const CardioidSteeringStatistics stats = steeringStatistics(ambix, window);
  const DirectionOfArrival doa = options.direction_method == DirectionMethod::kGridSearch
                                     ? directionByGridSearch(stats, options.grid_step_rad)
                                     : directionClosedForm(stats);
  const double flat_below_hz = options.lpc_flat_below_hz.value_or(1.0 / options.analysis_window_s);
  const LpcModel lpc = levinsonDurbin(autocorrelationFlatBelow(segment, options.lpc_order, 2.0 * kPi * flat_below_hz / fs),
                                      options.lpc_order);
  EarlyReflection r;
  r.time_of_arrival_s = time_s;
  r.level = std::sqrt(energy);  // A_k = sqrt(E_k)
  r.azimuth_rad = doa.azimuth_rad;
  r.elevation_rad = doa.elevation_rad;
  r.confidence = stats.directness();
  r.lpc = lpc.a;
  r.lpc_gain = lpc.gain;
  r.sos = allPoleToSections(lpc.a, lpc.gain);
  return r;
}

EarlyReflection analyseArrival(const AudioBuffer& ambix, double time_s, const EarlyReflectionOptions& options) {
  const std::vector<float>& w = ambix.channels[kAcnW];
  return analyseArrival(ambix, time_s, options, [&w](std::size_t n) { return static_cast<double>(w[n]); });
}

// The direct sound, the first strong arrival: of the group-delay arrivals near the ISO
// 3382-1 onset sample that pass the phase-slope test, the earliest within
// direct_onset_threshold_db of the strongest of them (a direct sound weakened by the
// source's directivity still comes before a louder reflection). Falls back to the
// strongest crossing there, then to the onset sample itself (e.g. for a step, whose group
// delay never crosses zero).
ArrivalCandidate findDirectArrival(const std::vector<ArrivalCandidate>& raw, const GroupDelayFunction& gd,
                                   std::size_t onset, const EarlyReflectionOptions& options) {
  const double onset_s = static_cast<double>(onset) / gd.sample_rate_hz;
  std::vector<ArrivalCandidate> near;
  for (const auto& c : raw) {
    if (c.time_s >= onset_s - kDirectSearchBeforeS && c.time_s <= onset_s + kDirectSearchAfterS) near.push_back(c);
  }
  const auto stronger = [](const ArrivalCandidate& a, const ArrivalCandidate& b) { return a.local_energy < b.local_energy; };
  std::vector<ArrivalCandidate> clean;
  for (const auto& c : near) {
    if (std::abs(c.slope + 1.0) <= options.onsets.max_slope_deviation) clean.push_back(c);
  }
  if (!clean.empty()) {
    const double floor = std::max_element(clean.begin(), clean.end(), stronger)->local_energy *
                         std::pow(10.0, -options.direct_onset_threshold_db / 10.0);
    for (const auto& c : clean) {
      if (c.local_energy >= floor) return c;  // in time order: the first strong one
    }
  }
  if (!near.empty()) return *std::max_element(near.begin(), near.end(), stronger);
  ArrivalCandidate fallback;
  fallback.time_s = onset_s;
  if (onset >= gd.first_centre && onset - gd.first_centre < gd.local_energy.size()) {
    fallback.local_energy = gd.local_energy[onset - gd.first_centre];
  }
  return fallback;
}

// Distances along the reflections' paths (the image sources' distances): the direct
// sound's, plus the extra path c * delay of each later arrival.
void placeImageSources(std::vector<EarlyReflection>& result, const EarlyReflectionOptions& options) {
  const double c = options.speed_of_sound_m_s;
  const double direct_s = result.front().time_of_arrival_s;
  const double direct_m = options.direct_distance_m.value_or(c * direct_s);
  for (EarlyReflection& r : result) r.distance_m = direct_m + c * (r.time_of_arrival_s - direct_s);
}

std::vector<EarlyReflection> selectReflections(std::vector<EarlyReflection> later, double direct_level,
                                               const EarlyReflectionOptions& options) {
  if (options.selection == ReflectionSelection::kAboveLevelThreshold) {
    const double floor = direct_level * std::pow(10.0, options.level_threshold_db / 20.0);
    later.erase(std::remove_if(later.begin(), later.end(), [&](const EarlyReflection& r) { return r.level < floor; }),
                later.end());
  }
  std::stable_sort(later.begin(), later.end(),
                   [](const EarlyReflection& a, const EarlyReflection& b) { return a.level > b.level; });
  if (later.size() > options.max_reflections) later.resize(options.max_reflections);
  std::sort(later.begin(), later.end(),
            [](const EarlyReflection& a, const EarlyReflection& b) { return a.time_of_arrival_s < b.time_of_arrival_s; });
  return later;
}

// The arrivals by matching pursuit (matched_arrivals.h): times, directions and the
// reflections' levels from the pursuit. A reflection's level is its own amplitude in W (the
// square root of its energy, the paper's A_k for an isolated arrival), not the energy of
// the window around it, and its spectrum is fitted on the window of the arrival alone (W
// with the pursuit's other arrivals taken out): the pursuit parts arrivals 0.1 ms apart,
// and a 2 ms window round each holds its neighbours too, so window levels count the direct
// sound again in an arrival kept just after it and a cluster of close reflections once per
// member (on the measured RIRs that lengthens the resynthesis's EDT by several per cent,
// docs/rsao.md), and a window's spectrum holds the neighbours' low frequencies, which add
// coherently there, and their comb. The direct sound's level is its window's, its other
// arrivals taken out too: the window holds the loudspeaker's response after the atom's
// 0.25 ms, which belongs to the direct sound (and which the pursuit's guard keeps there),
// but a floor reflection 0.5 ms after it does not (counted, it makes the direct sound up to
// 1.1 dB too loud in the near-direct rooms of reflection_rooms.h, and the DRR with it). Its
// spectrum is its window's: the loudspeaker's response is its spectrum.
std::vector<EarlyReflection> matchedReflections(const AudioBuffer& ambix, double direct_time_s, double limit_s,
                                                const EarlyReflectionOptions& options) {
  const MatchedPursuit pursuit = matchedPursuit(ambix, direct_time_s, limit_s, options.matched);
  const std::vector<MatchedArrival>& arrivals = pursuit.arrivals;
  const std::vector<float>& w = ambix.channels[kAcnW];
  const std::size_t residual_end = pursuit.residual_first + pursuit.w_residual.size();
  // W with every arrival but m taken out: the pursuit's residual plus m's own atom, within
  // the span the pursuit searched.
  const auto alone = [&](const MatchedArrival& m) {
    return [&](std::size_t n) {
      if (n < pursuit.residual_first || n >= residual_end) return static_cast<double>(w[n]);
      const bool in_atom = n >= m.w_first && n < m.w_first + m.w_model.size();
      return pursuit.w_residual[n - pursuit.residual_first] + (in_atom ? m.w_model[n - m.w_first] : 0.0);
    };
  };
  const auto withOwnDirection = [&](EarlyReflection r, const MatchedArrival& m) {
    const DirectionOfArrival doa = directionFromVector(m.direction);
    r.azimuth_rad = doa.azimuth_rad;
    r.elevation_rad = doa.elevation_rad;
    // The arrival's own projection, not the window it shares with its neighbours: a
    // reflection 0.3 ms from a stronger one is pointed right, and its confidence says so.
    r.confidence = m.directness;
    return r;
  };
  const MatchedArrival& direct = arrivals.front();
  std::vector<EarlyReflection> result{withOwnDirection(analyseArrival(ambix, direct.time_s, options), direct)};
  result.front().level = analyseArrival(ambix, direct.time_s, options, alone(direct)).level;
  // Strongest by the arrival's own amplitude in the pursuit: the window's level also holds
  // its neighbours, which would rank a weak reflection beside a strong one above a lone
  // reflection stronger than it.
  std::vector<std::size_t> order;
  const double floor = result.front().level * std::pow(10.0, options.level_threshold_db / 20.0);
  std::vector<EarlyReflection> reflections(arrivals.size());
  for (std::size_t k = 1; k < arrivals.size(); ++k) {
    reflections[k] = withOwnDirection(analyseArrival(ambix, arrivals[k].time_s, options, alone(arrivals[k])), arrivals[k]);
    reflections[k].level = std::abs(arrivals[k].amplitude);
    if (options.selection == ReflectionSelection::kAboveLevelThreshold && reflections[k].level < floor) continue;
    order.push_back(k);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::abs(arrivals[a].amplitude) > std::abs(arrivals[b].amplitude);
  });
  if (order.size() > options.max_reflections) order.resize(options.max_reflections);
  std::sort(order.begin(), order.end());  // arrivals are in time order
  for (std::size_t k : order) result.push_back(std::move(reflections[k]));
  return result;
}

}  // namespace

void validateEarlyReflectionOptions(const EarlyReflectionOptions& o) {
  validateGroupDelayOnsetOptions(o.onsets);
  validateMatchedArrivalOptions(o.matched);
  std::ostringstream os;
  os << kWhat << ": ";
  if (o.mixing_time_s && !(*o.mixing_time_s > 0.0 && std::isfinite(*o.mixing_time_s))) {
    os << "mixing_time_s = " << *o.mixing_time_s << " s; give a positive time from the first sample, or none";
  } else if (!(o.default_early_duration_s > 0.0) || !std::isfinite(o.default_early_duration_s)) {
    os << "default_early_duration_s = " << o.default_early_duration_s << " s; use a positive duration, e.g. 0.08";
  } else if (!(o.direct_onset_threshold_db > 0.0) || !std::isfinite(o.direct_onset_threshold_db)) {
    os << "direct_onset_threshold_db = " << o.direct_onset_threshold_db << "; use a positive number of dB, e.g. 20";
  } else if (!(o.analysis_window_s >= 0.0005 && o.analysis_window_s <= 0.05)) {
    os << "analysis_window_s = " << o.analysis_window_s << " s; use 0.0005 to 0.05 s, e.g. 0.002";
  } else if (o.direction_method == DirectionMethod::kGridSearch &&
             !(o.grid_step_rad > 0.0 && o.grid_step_rad <= 0.25 * kPi)) {
    os << "grid_step_rad = " << o.grid_step_rad << "; use a step in (0, pi/4], e.g. 0.01745 (1 degree)";
  } else if (o.lpc_order < 1 || o.lpc_order > 40) {
    os << "lpc_order = " << o.lpc_order << "; use 1 to 40 (the paper uses 9)";
  } else if (o.lpc_flat_below_hz && !(*o.lpc_flat_below_hz >= 0.0 && *o.lpc_flat_below_hz < 0.5 * kInternalSampleRateHz)) {
    os << "lpc_flat_below_hz = " << *o.lpc_flat_below_hz << " Hz; use 0 (the paper's fit) up to below 24000 Hz, or none";
  } else if (!(o.speed_of_sound_m_s > 0.0) || !std::isfinite(o.speed_of_sound_m_s)) {
    os << "speed_of_sound_m_s = " << o.speed_of_sound_m_s << "; use a positive speed, e.g. 343";
  } else if (o.direct_distance_m && !(*o.direct_distance_m > 0.0 && std::isfinite(*o.direct_distance_m))) {
    os << "direct_distance_m = " << *o.direct_distance_m << " m; give the source's positive distance, or none";
  } else if (!(o.level_threshold_db <= 0.0) || !std::isfinite(o.level_threshold_db)) {
    os << "level_threshold_db = " << o.level_threshold_db << "; use a finite level at or below 0 dB, e.g. -20";
  } else {
    return;
  }
  throw InputError(os.str());
}

std::vector<EarlyReflection> estimateEarlyReflections(const AudioBuffer& ambix, const EarlyReflectionOptions& options) {
  validateEarlyReflectionOptions(options);
  validateInput(ambix, options);
  const double fs = ambix.sample_rate_hz;
  const auto& w = ambix.channels[kAcnW];
  const std::size_t frames = ambix.frameCount();

  const std::size_t onset = findDirectSoundOnset(w, options.direct_onset_threshold_db);
  // Group delay from just before the onset to the end of the early part. The direct
  // sound's own time is not known yet, so the range covers its search window after the
  // onset in any case, and the default early part from the latest it can be.
  const double onset_s = static_cast<double>(onset) / fs;
  double end_s = onset_s + kDirectSearchAfterS;
  end_s = options.mixing_time_s ? std::max(end_s, *options.mixing_time_s) : end_s + options.default_early_duration_s;
  const auto before = static_cast<std::size_t>(std::ceil(kDirectSearchBeforeS * fs)) + 1;
  const std::size_t first = onset > before ? onset - before : 0;
  const std::size_t end = std::min(frames, static_cast<std::size_t>(std::ceil(end_s * fs)) + 2);
  const GroupDelayFunction gd =
      energyWeightedGroupDelay(w, fs, first, end, groupDelayWindowLength(options.onsets.window_s, fs));
  const std::vector<ArrivalCandidate> raw = negativeGoingZeroCrossings(gd);

  const ArrivalCandidate direct = findDirectArrival(raw, gd, onset, options);
  const double limit_s = options.mixing_time_s ? *options.mixing_time_s : direct.time_s + options.default_early_duration_s;
  if (options.onset_method == OnsetMethod::kMatchedPursuit) {
    std::vector<EarlyReflection> result = matchedReflections(ambix, direct.time_s, limit_s, options);
    placeImageSources(result, options);
    return result;
  }
  std::vector<ArrivalCandidate> later;
  for (const auto& c : raw) {
    if (c.time_s >= direct.time_s + options.onsets.min_separation_s && c.time_s <= limit_s) later.push_back(c);
  }
  later = pruneCandidates(later, gd, direct.local_energy, options.onsets);

  std::vector<EarlyReflection> result{analyseArrival(ambix, direct.time_s, options)};
  std::vector<EarlyReflection> reflections;
  reflections.reserve(later.size());
  for (const auto& c : later) reflections.push_back(analyseArrival(ambix, c.time_s, options));
  for (auto& r : selectReflections(std::move(reflections), result.front().level, options)) result.push_back(std::move(r));
  placeImageSources(result, options);
  return result;
}

}  // namespace room_reverb::core
