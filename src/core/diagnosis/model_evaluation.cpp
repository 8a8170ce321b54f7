#include "room_reverb/diagnosis/model_evaluation.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <optional>

#include "room_reverb/common/error.h"
#include "room_reverb/evaluation/parameter_comparison.h"
#include "room_reverb/diagnosis/reflection_evidence.h"
#include "room_reverb/evaluation/simulated_pairs.h"

namespace room_reverb::core {
namespace {

// The ISO 3382 parameters the diagnosis scores. C50 and Ts say little that C80, D50 and
// EDT do not; T30 carries the late slope that coupled volumes bend.
constexpr std::array<ComparedParameter, 6> kScored = {ComparedParameter::kT20, ComparedParameter::kT30,
                                                      ComparedParameter::kEdt, ComparedParameter::kC80,
                                                      ComparedParameter::kD50, ComparedParameter::kDrr};

bool wanted(const std::vector<double>& bands, double nominal_hz) {
  return std::any_of(bands.begin(), bands.end(), [&](double b) { return std::abs(std::log2(b / nominal_hz)) < 1.0 / 6.0; });
}

void addRows(const std::vector<BandComparison>& rows, int pair, bool split_by_pair, const EvaluationSettings& settings,
             std::vector<ErrorTerm>& terms) {
  for (const BandComparison& row : rows) {
    if (!wanted(settings.bands_hz, row.nominal_hz)) continue;
    for (ComparedParameter p : kScored) {
      const auto& e = row.error_jnd[static_cast<std::size_t>(p)];
      if (!e || !std::isfinite(*e)) continue;
      ErrorTerm term;
      term.pair = pair;
      term.group = toString(p);
      term.band_hz = row.nominal_hz;
      term.error_jnd = *e;
      term.held_out = split_by_pair ? isHeldOutPair(static_cast<std::size_t>(pair)) : isHeldOutBand(row.nominal_hz);
      terms.push_back(term);
    }
  }
}

// One term per entry of a level profile (the early windows, or the steered directions)
// in each band both profiles have; 1 dB counts as 1 JND, the JND of a level. `first`
// skips entries that are references (the early profile's window 0 is the direct sound).
template <typename Profile>
void addLevels(const Profile& simulated, const Profile& measured, const char* group, std::size_t first, int pair,
               bool split_by_pair, std::vector<ErrorTerm>& terms) {
  for (std::size_t b = 0; b < measured.bands_hz.size(); ++b) {
    const auto it = std::find(simulated.bands_hz.begin(), simulated.bands_hz.end(), measured.bands_hz[b]);
    if (it == simulated.bands_hz.end()) continue;
    const auto& sim = simulated.level_db[static_cast<std::size_t>(it - simulated.bands_hz.begin())];
    const auto& meas = measured.level_db[b];
    for (std::size_t i = first; i < std::min(sim.size(), meas.size()); ++i) {
      ErrorTerm term;
      term.pair = pair;
      term.group = group;
      term.band_hz = measured.bands_hz[b];
      term.window = static_cast<int>(i);
      term.error_jnd = sim[i] - meas[i];
      term.held_out = split_by_pair ? isHeldOutPair(static_cast<std::size_t>(pair)) : isHeldOutBand(term.band_hz);
      terms.push_back(term);
    }
  }
}

// One term per pair, split by pair like the rest.
void addReflections(double error_jnd, int pair, std::vector<ErrorTerm>& terms) {
  ErrorTerm term;
  term.pair = pair;
  term.group = "reflections";
  term.error_jnd = error_jnd;
  term.held_out = isHeldOutPair(static_cast<std::size_t>(pair));
  terms.push_back(term);
}

}  // namespace

void score(Evaluation& evaluation, const MeasuredEvidence& evidence, const EvaluationSettings& settings) {
  evaluation.valid = true;
  evaluation.terms = errorTerms(evidence, evaluation.predictions, settings);
  evaluation.error_jnd = meanAbsoluteError(evaluation.terms, -1);
  // The fit part leaves the reflection term out: explained or not within 0.6 ms, it is a
  // step function of a fit's parameters and a poor objective (with it, the planted room
  // scale of seed 15 fitted 0.929 for 0.906). It judges fits on the held-out pairs.
  std::vector<ErrorTerm> fit_terms;
  std::copy_if(evaluation.terms.begin(), evaluation.terms.end(), std::back_inserter(fit_terms),
               [](const ErrorTerm& t) { return t.group != "reflections"; });
  evaluation.fit_error_jnd = meanAbsoluteError(fit_terms, 0);
  evaluation.heldout_error_jnd = meanAbsoluteError(evaluation.terms, 1);
}

AudioBuffer extendedResponse(const std::vector<float>& omni_response, const PairPrediction& prediction,
                             const MeasurementPair& pair, const ModelExtension& extension, const ModalRoom* modal_room) {
  AudioBuffer omni;
  omni.channels.push_back(omni_response);
  const double direct_delay_s = prediction.paths.empty() ? 0.0 : prediction.paths.front().delay_s;
  applyResponseExtensions(omni, extension, modal_room, pair, direct_delay_s, prediction.seed);
  return omni;
}

std::optional<EarlyDirectionProfile> predictedDirections(const AudioBuffer& extended, const PairPrediction& prediction) {
  if (prediction.simulated_velocity.size() != 3) return std::nullopt;
  // Only as far as X, Y and Z were kept, which is past the window.
  const std::vector<float>& w = extended.channels.front();
  const std::size_t length = std::min(w.size(), prediction.simulated_velocity.front().size());
  AudioBuffer ambix;
  ambix.sample_rate_hz = extended.sample_rate_hz;
  ambix.channels.emplace_back(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(length));
  for (const std::vector<float>& channel : prediction.simulated_velocity) {
    ambix.channels.emplace_back(channel.begin(), channel.begin() + static_cast<std::ptrdiff_t>(length));
  }
  return earlyDirectionProfile(ambix, prediction.analysis.metrics.onset_sample);
}

std::map<std::string, double> groupMeanAbsoluteErrors(const std::vector<ErrorTerm>& terms, int selection) {
  std::map<std::string, std::pair<double, int>> sums;
  for (const ErrorTerm& t : terms) {
    if (selection == 0 && t.held_out) continue;
    if (selection == 1 && !t.held_out) continue;
    auto& [sum, n] = sums[t.group];
    // A pair's reflection term sums reflections already capped one by one (a pair that
    // misses two strong ones is worse off than one that misses one).
    sum += t.group == "reflections" ? std::abs(t.error_jnd) : std::min(kTermCapJnd, std::abs(t.error_jnd));
    ++n;
  }
  std::map<std::string, double> means;
  for (const auto& [group, sum_n] : sums) means[group] = sum_n.first / sum_n.second;
  return means;
}

double meanAbsoluteError(const std::vector<ErrorTerm>& terms, int selection) {
  const std::map<std::string, double> groups = groupMeanAbsoluteErrors(terms, selection);
  if (groups.empty()) return 0.0;
  double total = 0.0;
  for (const auto& [group, mean] : groups) total += mean;
  return total / static_cast<double>(groups.size());
}

std::vector<ErrorTerm> errorTerms(const MeasuredEvidence& evidence, const std::vector<PairPrediction>& predictions,
                                  const EvaluationSettings& settings) {
  std::vector<ErrorTerm> terms;
  if (evidence.usesRirs()) {
    const bool split_by_pair = splitsByPair(evidence.rirs.size());
    for (std::size_t i = 0; i < evidence.rirs.size() && i < predictions.size(); ++i) {
      const MeasuredParameters measured = parametersFromReport(evidence.rirs[i].metrics);
      addRows(compareWithMeasured({predictions[i].analysis.metrics}, measured), static_cast<int>(i), split_by_pair,
              settings, terms);
      addLevels(predictions[i].analysis.early, evidence.rirs[i].early, "early", 1, static_cast<int>(i), split_by_pair,
                terms);
      if (settings.score_directions && evidence.rirs[i].directions && predictions[i].analysis.directions) {
        addLevels(*predictions[i].analysis.directions, *evidence.rirs[i].directions, "directions", 0,
                  static_cast<int>(i), split_by_pair, terms);
      }
      // From one pair there is no term: a panel is placed from that pair's reflections,
      // and the same reflections cannot also judge it.
      if (predictions[i].reflection_error_jnd && split_by_pair) {
        addReflections(*predictions[i].reflection_error_jnd, static_cast<int>(i), terms);
      }
    }
    return terms;
  }
  std::vector<MetricsReport> reports;
  for (const PairPrediction& p : predictions) reports.push_back(p.analysis.metrics);
  std::vector<BandComparison> rows = compareWithMeasured(reports, evidence.table);
  if (evidence.table.resolution == BandResolution::kThirdOctave) rows = thirdsToOctaves(rows);
  addRows(rows, -1, false, settings, terms);
  return terms;
}

ModelEvaluator::ModelEvaluator(const RoomUnderTest& room, const MeasuredEvidence& evidence, EvaluationSettings settings)
    : room_(room), evidence_(evidence), settings_(std::move(settings)) {
  const bool directional = std::any_of(evidence_.rirs.begin(), evidence_.rirs.end(),
                                       [](const PairEvidence& p) { return p.reflections.has_value(); });
  if (settings_.score_reflections && directional) given_scene_ = std::make_shared<const AcousticScene>(room_.scene({}));
  score_directions_ = settings_.score_directions &&
                      std::any_of(evidence_.rirs.begin(), evidence_.rirs.end(),
                                  [](const PairEvidence& p) { return p.directions.has_value(); });
  settings_.simulation.ambisonic_order = score_directions_ ? 1 : 0;
}

Evaluation ModelEvaluator::evaluate(const ModelExtension& extension, std::uint32_t seed_offset) const {
  return std::move(evaluateMany({{&extension, seed_offset}}).front());
}

std::vector<Evaluation> ModelEvaluator::evaluateAtSeeds(const ModelExtension& extension,
                                                        const std::vector<std::uint32_t>& seed_offsets) const {
  std::vector<EvaluationCase> cases;
  for (std::uint32_t offset : seed_offsets) cases.push_back({&extension, offset});
  return evaluateMany(cases);
}

// One case of evaluateMany: its scene and settings, and the requests of its pairs.
struct ModelEvaluator::PreparedCase {
  const ModelExtension* extension = nullptr;
  std::shared_ptr<const AcousticScene> scene;
  SimulationSettings settings;
  std::shared_ptr<const ModalRoom> modal_room;
  std::vector<SimulationRequest> requests;
};

ModelEvaluator::PreparedCase ModelEvaluator::prepare(const EvaluationCase& c, const PreparedCase* same_model) const {
  PreparedCase p;
  p.extension = c.extension;
  if (same_model) {
    p.scene = same_model->scene;
    p.settings = same_model->settings;
    p.modal_room = same_model->modal_room;
  } else {
    p.scene = std::make_shared<const AcousticScene>(room_.scene(*c.extension));
    p.settings = settings_.simulation;
    p.settings.air = room_.airWith(*c.extension);
    if (c.extension->modes) p.modal_room = std::make_shared<const ModalRoom>(modalRoomFor(*p.scene, p.settings.air));
    if (c.extension->directivity) p.settings.directivity = *c.extension->directivity;
    if (c.extension->diffraction_scattering) p.settings.diffraction_scattering = true;
    if (c.extension->wave_low_band) p.settings.low_band = LowBandMethod::kWave;
    if (c.extension->third_octave_bands) p.settings.bands = BandResolution::kThirdOctave;
  }
  // Pair i at seed offset k: pairSeed(base + 7919 k, i), with the thread count its place in
  // the rounds of one evaluation gives it, wherever it runs.
  SimulationSettings base = p.settings;
  base.rays.seed = settings_.simulation.rays.seed + 7919u * c.seed_offset;
  p.requests = pairRequests(evidence_.positions, base);
  return p;
}

void ModelEvaluator::predictPair(const PreparedCase& p, std::size_t i, SimulationResult& result,
                                 PairPrediction& prediction) const {
  const ModelExtension& extension = *p.extension;
  const MeasurementPair& pair = evidence_.positions[i];
  prediction.simulated_omni = std::move(result.impulse_response.channels.front());
  prediction.paths = std::move(result.paths);
  prediction.seed = p.requests[i].settings.rays.seed;
  if (given_scene_ && i < evidence_.rirs.size() && evidence_.rirs[i].reflections) {
    prediction.reflection_error_jnd =
        reflectionMismatchJnd(*evidence_.rirs[i].reflections, prediction.paths, pair, *given_scene_,
                              result.speed_of_sound_m_s);
  }
  const AudioBuffer extended = extendedResponse(prediction.simulated_omni, prediction, pair, extension,
                                                p.modal_room.get());
  prediction.analysis = analysePair(pair, extended);
  if (score_directions_ && i < evidence_.rirs.size() && evidence_.rirs[i].directions) {
    const std::size_t keep = prediction.analysis.metrics.onset_sample +
                             static_cast<std::size_t>((EarlyDirectionOptions{}.end_s + 0.02) * extended.sample_rate_hz);
    for (std::size_t c = 1; c < 4; ++c) {
      std::vector<float>& channel = result.impulse_response.channels[c];
      channel.resize(std::min(channel.size(), keep));
      prediction.simulated_velocity.push_back(std::move(channel));
    }
    prediction.analysis.directions = predictedDirections(extended, prediction);
  }
}

std::vector<Evaluation> ModelEvaluator::evaluateMany(const std::vector<EvaluationCase>& cases) const {
  evaluations_ += static_cast<int>(cases.size());
  std::vector<Evaluation> evaluations(cases.size());
  const auto invalid = [](const std::string& reason) {
    Evaluation evaluation;
    evaluation.reason = reason;
    return evaluation;
  };
  // Every case's scene and requests first; a case of the same extension as the last one
  // prepared shares its scene.
  std::vector<std::optional<PreparedCase>> prepared(cases.size());
  const PreparedCase* last = nullptr;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    try {
      prepared[k] = prepare(cases[k], last && last->extension == cases[k].extension ? last : nullptr);
      last = &*prepared[k];
    } catch (const InputError& e) {
      evaluations[k] = invalid(e.what());
    }
  }
  // Each pair replayed from the paths kept at its seed where only absorption, air or
  // directivity differ (path_ledger.h); the rest traced: a pair whose seed has no paths kept
  // yet in this process, keeping them, and the others by the runner or here. Which pairs
  // are replayed depends only on the cases, so a runner changes nothing in the results.
  std::vector<std::vector<SimulationResult>> results(cases.size());
  std::vector<std::string> refused(cases.size());
  struct Trace {
    std::size_t k, i;
    bool keep;
  };
  std::vector<Trace> keepers, traces, replays, deferred;
  std::map<std::pair<std::uint32_t, std::size_t>, bool> keeping;  // seeds whose paths this batch keeps
  for (std::size_t k = 0; k < cases.size(); ++k) {
    if (!prepared[k]) continue;
    const PreparedCase& p = *prepared[k];
    results[k].resize(p.requests.size());
    for (std::size_t i = 0; i < p.requests.size(); ++i) {
      const SimulationRequest& r = p.requests[i];
      const auto key = std::make_pair(r.settings.rays.seed, i);
      if (kept_paths_.count(key)) {
        replays.push_back({k, i, false});
        continue;
      }
      // Paths are kept at the base seed only: the candidates of every fit are evaluated
      // there; the noise seeds' evaluations of a few confirmed fits are not worth the memory.
      const bool may_keep = settings_.replay_paths && cases[k].seed_offset == 0 &&
                            r.settings.mode == SimulationMode::kAccurate && kept_bytes_ < kKeptPathsBudgetBytes;
      if (!may_keep) {
        traces.push_back({k, i, false});
      } else if (keeping.count(key)) {
        deferred.push_back({k, i, false});  // replayed from this batch's keeper
      } else {
        keeping[key] = true;
        keepers.push_back({k, i, true});
      }
    }
  }
  // Traced here: the keepers, and the other traces when there is no runner.
  const auto traceHere = [&](const std::vector<Trace>& here) {
    std::vector<std::string> errors(here.size());
    runInRounds(here.size(), settings_.simulation.rays.threads, [&](std::size_t j, int) {
      const Trace& t = here[j];
      const PreparedCase& p = *prepared[t.k];
      const SimulationRequest& r = p.requests[t.i];
      try {
        // A trace records at most what the budget has left when the traces start.
        results[t.k][t.i] = simulateRoom(*p.scene, r.source_m, r.listener_m, r.settings, {},
                                         t.keep ? kKeptPathsBudgetBytes - kept_bytes_ : 0);
      } catch (const InputError& e) {
        errors[j] = e.what();
      }
    });
    for (std::size_t j = 0; j < here.size(); ++j) {
      const Trace& t = here[j];
      if (!errors[j].empty()) {
        if (refused[t.k].empty()) refused[t.k] = errors[j];
        continue;
      }
      SimulationResult& result = results[t.k][t.i];
      if (!t.keep || !result.ledger) continue;
      const std::size_t bytes = result.ledger->bytes();
      if (kept_bytes_ + bytes <= kKeptPathsBudgetBytes) {
        SimulationResult paths;
        paths.ledger = result.ledger;
        paths.stats = result.stats;
        kept_paths_.emplace(std::make_pair(prepared[t.k]->requests[t.i].settings.rays.seed, t.i), std::move(paths));
        kept_bytes_ += bytes;
      }
      result.ledger = nullptr;
    }
  };
  std::vector<Trace> remote;
  if (settings_.runner) {
    remote = std::move(traces);
    traces.clear();
  }
  keepers.insert(keepers.end(), traces.begin(), traces.end());
  traceHere(keepers);
  // The replays, two (or the thread count) at a time as traces run: of the paths kept
  // before this batch and of its keepers'. A refused one, or one whose keeper kept no
  // paths, is traced.
  replays.insert(replays.end(), deferred.begin(), deferred.end());
  std::vector<char> replayed(replays.size(), 0);
  runInRounds(replays.size(), settings_.simulation.rays.threads, [&](std::size_t j, int) {
    const Trace& t = replays[j];
    const PreparedCase& p = *prepared[t.k];
    const SimulationRequest& r = p.requests[t.i];
    const auto kept = kept_paths_.find(std::make_pair(r.settings.rays.seed, t.i));
    if (kept == kept_paths_.end() || !refused[t.k].empty()) return;
    std::string why_not;
    if (auto result = replaySimulation(kept->second, *p.scene, r.source_m, r.listener_m, r.settings, why_not)) {
      results[t.k][t.i] = std::move(*result);
      results[t.k][t.i].ledger = nullptr;
      replayed[j] = 1;
    }
  });
  std::vector<Trace> again;
  for (std::size_t j = 0; j < replays.size(); ++j) {
    if (replayed[j]) {
      ++replayed_;
    } else if (refused[replays[j].k].empty()) {
      (settings_.runner ? remote : again).push_back(replays[j]);
    }
  }
  traceHere(again);
  if (!remote.empty()) {
    // A runner gets every traced pair of every case at once, so that as many simulators as
    // there are simulations can work together; each result is the same as in this process.
    std::vector<const AcousticScene*> scenes;
    std::vector<SimulationRequest> requests;
    std::vector<std::size_t> scene_of;
    for (const Trace& t : remote) {
      const PreparedCase& p = *prepared[t.k];
      if (scenes.empty() || scenes.back() != p.scene.get()) scenes.push_back(p.scene.get());
      requests.push_back(p.requests[t.i]);
      scene_of.push_back(scenes.size() - 1);
    }
    try {
      std::vector<SimulationResult> out = settings_.runner->simulateScenes(scenes, requests, scene_of, nullptr);
      for (std::size_t j = 0; j < remote.size(); ++j) results[remote[j].k][remote[j].i] = std::move(out[j]);
    } catch (const InputError&) {
      // A request the room refuses: each one again on its own, to tell which case it was.
      for (const Trace& t : remote) {
        const PreparedCase& p = *prepared[t.k];
        if (!refused[t.k].empty()) continue;
        try {
          results[t.k][t.i] = std::move(settings_.runner->simulate(*p.scene, {p.requests[t.i]}, nullptr).front());
        } catch (const InputError& e) {
          refused[t.k] = e.what();
        }
      }
    }
  }
  // Every pair of every case analysed in parallel: a response's analysis (band filters,
  // decay fits) does not parallelise as the tracer does, and one case's few pairs leave
  // threads idle.
  std::vector<std::pair<std::size_t, std::size_t>> analyses;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    if (!prepared[k]) continue;
    if (!refused[k].empty()) {
      evaluations[k] = invalid(refused[k]);
      continue;
    }
    evaluations[k].predictions.resize(evidence_.positions.size());
    for (std::size_t i = 0; i < evidence_.positions.size(); ++i) analyses.emplace_back(k, i);
  }
  std::vector<std::string> failed(analyses.size());
  runInRounds(analyses.size(), settings_.simulation.rays.threads, [&](std::size_t j, int) {
    const auto [k, i] = analyses[j];
    try {
      predictPair(*prepared[k], i, results[k][i], evaluations[k].predictions[i]);
    } catch (const InputError& e) {
      failed[j] = e.what();
    }
  });
  for (std::size_t j = analyses.size(); j-- > 0;) {
    if (!failed[j].empty()) refused[analyses[j].first] = failed[j];  // the first pair's reason stays
  }
  for (std::size_t k = 0; k < cases.size(); ++k) {
    if (!prepared[k] || !evaluations[k].reason.empty()) continue;
    if (!refused[k].empty()) {
      evaluations[k] = invalid(refused[k]);
    } else {
      score(evaluations[k], evidence_, settings_);
    }
    results[k].clear();
  }
  return evaluations;
}

}  // namespace room_reverb::core
